#pragma once
// The options of `glarelab psf` (runner/cli/command_psf.cpp): their values, and the handles of
// those whose presence decides something (an option the chosen model does not use is refused).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "glare/glare_backend_kind.h"
#include "runner/cli/psf_refraction.h"

namespace glarelab::cli {

struct PsfArguments {
  double pupil_diameter_mm = 4.0;
  double wavelength_nm = 575.0;
  bool spectral = false;
  int wavelength_samples = 32;
  int grid_px = 512;
  double aperture_width_mm = 10.0;
  int supersampling = 2;
  std::string fresnel = "defocus";
  double defocus_dioptres = 0.0;
  GlareBackendRequest backend = GlareBackendRequest::cpu;
  bool gratings = false;
  std::string mode;  // empty: a bare pupil (with --gratings); else the eye model in this mode
  double time_s = 0.0;
  std::uint64_t seed = 1;
  std::string components = "all";
  // The human eye by default, as in sessions ([glare] model): the eye model in --mode (dynamic when
  // not given) adapted to --field-luminance-cd-m2, its spectral PSF joined to CIE 146.
  std::string model = "human";
  double field_luminance_cd_m2 = 100.0;  // the eye model's field luminance (its pupil, Eq. 1-2)
  std::string eye_from;  // an experiment file whose [glare.eye] sets the eye model (protocols/glare_eye_file.h)
  std::string regime = "photopic";
  bool flare_lines = false;        // Spencer's flare lines (section 3.2) in the image
  std::uint64_t flare_seed = 1;    // their draws
  double age_years = 25.0;
  double pigmentation = 0.5;
  std::string far_field = "spencer";
  std::vector<double> handover_deg;  // inner, outer; empty: the default for the wave PSF's reach
  // A desktop display at about 60 cm (0.25 mm pixels): 512 px span 12.8 degrees.
  double degrees_per_pixel = 0.025;
  std::string profile_csv;
  std::string out;
  RefractionArguments refraction;
};

// The options whose presence decides something, kept from their registration.
struct PsfOptionHandles {
  CLI::Option* pupil = nullptr;
  CLI::Option* defocus = nullptr;
  CLI::Option* backend = nullptr;
  CLI::Option* regime = nullptr;
  CLI::Option* flare_lines = nullptr;
  CLI::Option* age = nullptr;
  CLI::Option* pigmentation = nullptr;
  CLI::Option* far_field = nullptr;
  CLI::Option* handover = nullptr;
  CLI::Option* dpp = nullptr;
  CLI::Option* field_luminance = nullptr;
  CLI::Option* eye_from = nullptr;
  CLI::Option* cylinder = nullptr;
  CLI::Option* axis = nullptr;
  CLI::Option* amplitude = nullptr;
  std::vector<CLI::Option*> refraction;  // any of them turns the observer's refraction on
  std::vector<const CLI::Option*> wave;  // the wave-optics eye's, refused with --model spencer or cie
};

// Registers every option of the psf command on `command`, bound to `args` (both must outlive it).
void add_psf_options(CLI::App* command, PsfArguments& args, PsfOptionHandles& handles);

}  // namespace glarelab::cli
