#pragma once
// The observer's refraction of `glarelab psf` (docs/REFRACTION.md, "The psf command"): the eye's
// error as its correcting prescription, the spectacles worn, the fixation distance and the
// accommodation amplitude, read into the residual error at the retina; and the check that the
// largest grid samples its phase.
#include <limits>
#include <string>

#include "glare/eye/aperture_geometry.h"
#include "glare/refraction/eye_refraction.h"
#include "glare/glare_backend.h"

namespace glarelab::cli {

// A number as psf prints it: 4 significant digits.
std::string psf_text(double value);

inline constexpr int kLargestGridPx = 8192;  // the largest --grid

// The refraction options' values.
struct RefractionArguments {
  double sphere_dioptres = 0.0;
  double cylinder_dioptres = 0.0;
  double axis_deg = 0.0;
  std::string spectacles;
  double viewing_distance_m = std::numeric_limits<double>::infinity();
  double accommodation_amplitude_dioptres = kSchematicAccommodationAmplitudeDioptres;
  double vertex_distance_mm = 1e3 * kDefaultVertexDistance_m;
};

// The observer's refraction set on the command line: the options that make it and what it gives.
struct ObserverRefraction {
  bool active = false;
  std::string flags;  // the refraction options given, for messages ("--sphere-dioptres, --axis-deg")
  FixationRefraction fixation;
  DioptricPower ocular_refraction;
  std::string summary;  // printed once every refusal is past
};

// The eye's error, the lenses worn and the fixation distance give the residual error E at the
// retina (glare/refraction/eye_refraction.h), the pupil phase's sphero-cylindrical part: fills `refraction`
// (active, with its flags) and geometry.refraction_error. The amplitude is the one given, else
// Hofstetter's for the age given, else the schematic eye's. Plus cylinders are transposed and said
// so on stderr. Throws ConfigError naming the flag for spectacles not in front of the fixated point
// and for what glare/refraction/eye_refraction.h refuses.
void read_observer_refraction(const RefractionArguments& args, bool amplitude_given, bool age_given, double age_years,
                              ObserverRefraction& refraction, ApertureGeometry& geometry);

// check_grid's defocus refusal for the refraction's sphero-cylindrical phase: the phase of its
// strongest meridian (glare/refraction/astigmatic_phase.h) at every wavelength computed must be sampled by the
// largest grid, else no grid the program has can take it (ConfigError naming `flags`).
void check_refraction_sampling(const ApertureGeometry& geometry, const PsfOptions& options, const std::string& flags);

}  // namespace glarelab::cli
