#include "runner/cli/command_psf_luidolt.h"

#include <iostream>
#include <set>
#include <string>

#include "core/errors.h"
#include "glare/analytic/hybrid_handover.h"
#include "glare/eye/eye_model.h"
#include "protocols/glare_eye_file.h"
#include "glare/wave/luidolt_kernel.h"
#include "glare/wave/psf_exr.h"
#include "glare/wave/psf_profile.h"
#include "runner/cli/psf_refraction.h"

namespace glarelab::cli {
namespace {

const SourceLocation kWhere{"psf", 0, 0};

// The options Luidolt's kernel takes; any other given is refused rather than ignored.
const std::set<std::string> kLuidoltOptions = {"--pupil-diameter-mm", "--wavelength-samples", "--grid",
                                               "--aperture-width-mm", "--mode", "--eye-from", "--time-s", "--seed"};

void refuse_other_options(const PsfOptionHandles& handles) {
  std::vector<const CLI::Option*> options = handles.wave;
  for (const CLI::Option* option : {handles.regime, handles.age, handles.pigmentation, handles.far_field, handles.handover,
                                    handles.dpp, handles.backend, handles.defocus})
    options.push_back(option);
  for (const CLI::Option* option : options)
    if (option->count() > 0 && !kLuidoltOptions.contains(option->get_name()))
      throw ConfigError(kWhere, option->get_name(),
                        "does not apply to --model luidolt (its kernel takes --pupil-diameter-mm or --mode/--eye-from/--time-s/--seed, "
                        "--grid, --wavelength-samples and --aperture-width-mm)");
}

const CLI::Option* named(const PsfOptionHandles& handles, const std::string& name) {
  for (const CLI::Option* option : handles.wave)
    if (option->get_name() == name) return option;
  return nullptr;
}

}  // namespace

int run_luidolt_psf(const PsfArguments& args, const PsfOptionHandles& handles) {
  refuse_other_options(handles);
  LuidoltKernelOptions options;
  options.grid_px = args.grid_px;
  options.wavelength_count = args.wavelength_samples;
  if (const CLI::Option* width = named(handles, "--aperture-width-mm"); width != nullptr && width->count() > 0)
    options.aperture_width_mm = args.aperture_width_mm;
  if (options.wavelength_count < 2)
    throw ConfigError(kWhere, "--wavelength-samples", "Luidolt's Eq. 5.13 needs k + 1 >= 2 wavelengths");
  double pupil_mm = args.pupil_diameter_mm;
  std::uint64_t seed = args.seed;
  if (!args.eye_from.empty() && args.mode.empty())
    throw ConfigError(kWhere, "--eye-from", "sets the eye model, which --model luidolt takes only with --mode");
  if (!args.mode.empty()) {
    const GlareMode mode = parse_glare_mode(args.mode);
    if (mode == GlareMode::control) throw ConfigError(kWhere, "--mode", "control has no glare kernel");
    EyeParameters parameters;
    if (!args.eye_from.empty()) read_glare_eye_file(args.eye_from, parameters);
    parameters.mode = mode;
    if (handles.pupil->count() == 0) pupil_mm = EyeModel(parameters, args.seed).state_at(args.time_s).pupil_diameter_mm;
  }
  if (pupil_mm > options.aperture_width_mm)
    throw ConfigError(kWhere, "--pupil-diameter-mm",
                      "the pupil (" + psf_text(pupil_mm) + " mm) is wider than the particle texture (" +
                          psf_text(options.aperture_width_mm) + " mm, --aperture-width-mm)");
  LuidoltKernel kernel;
  try {
    kernel = luidolt_kernel(pupil_mm, seed, options);
  } catch (const LuidoltSamplingError& error) {
    throw ConfigError(kWhere, "--grid", error.what());
  }
  std::cout << "psf: luidolt: " << luidolt_description(options) << "\n";
  if (!kernel.sampling_note.empty()) std::cout << "psf: " << kernel.sampling_note << "\n";
  std::cout << "psf: pupil " << psf_text(pupil_mm) << " mm, seed " << seed << ": particles cover "
            << psf_text(100.0 * kernel.covered_fraction) << " % of the pupil; the bright centre holds "
            << psf_text(100.0 * kernel.centre_share) << " % of each channel\n";
  const Psf& psf = kernel.psf;
  if (!args.out.empty()) {
    write_psf_exr(args.out, psf);
    std::cout << "psf: wrote " << args.out << ": luidolt, " << psf.size_px << "x" << psf.size_px << " px, R,G,B, "
              << psf.degrees_per_pixel << " deg/px\n";
  }
  if (!args.profile_csv.empty()) {
    // Every wavelength's copy is whole out to the 380 nm copy's edge (M beyond the grid is unknown).
    const double reach_deg = wave_psf_reach_deg(psf.size_px, psf.degrees_per_pixel);
    const std::vector<ProfilePoint> points =
        image_profile_per_sr(psf, PixelLayout::uniform_angle, profile_angles_deg(), reach_deg);
    write_profile_csv(args.profile_csv, points);
    std::cout << "psf: wrote " << args.profile_csv << ": " << points.size() << " angles to " << psf_text(reach_deg)
              << " deg\n";
  }
  return 0;
}

}  // namespace glarelab::cli
