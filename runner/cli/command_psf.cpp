#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include "glare/analytic/analytic_psf.h"
#include "glare/eye/aperture_components.h"
#include "glare/refraction/astigmatic_phase.h"
#include "glare/refraction/chromatic_eye.h"
#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/analytic/display_psf_image.h"
#include "glare/eye/eye_model.h"
#include "glare/refraction/eye_refraction.h"
#include "glare/eye/fibre_gratings.h"
#include "glare/glare_backend.h"
#include "glare/analytic/hybrid_psf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_exr.h"
#include "glare/wave/psf_profile.h"
#include "glare/wave/psf_scale.h"
#include "core/errors.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/display/compute_context.h"

namespace glarelab::cli {
namespace {

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
  std::string backend = "cpu";
  bool gratings = false;
  std::string mode;  // empty: a bare pupil (with --gratings); else the eye model in this mode
  double time_s = 0.0;
  std::uint64_t seed = 1;
  std::string components = "all";
  std::string model = "ritschel";
  std::string regime = "photopic";
  double age_years = 25.0;
  double pigmentation = 0.5;
  std::string far_field = "spencer";
  std::vector<double> handover_deg;  // inner, outer; empty: the default for the wave PSF's reach
  // A desktop display at about 60 cm (0.25 mm pixels): 512 px span 12.8 degrees.
  double degrees_per_pixel = 0.025;
  std::string profile_csv;
  std::string out;
  // The observer's refraction (docs/REFRACTION.md): the eye's error as its correcting prescription,
  // the spectacles worn, the fixation distance and the accommodation amplitude.
  double sphere_dioptres = 0.0;
  double cylinder_dioptres = 0.0;
  double axis_deg = 0.0;
  std::string spectacles;
  double viewing_distance_m = std::numeric_limits<double>::infinity();
  double accommodation_amplitude_dioptres = kSchematicAccommodationAmplitudeDioptres;
  double vertex_distance_mm = 1e3 * kDefaultVertexDistance_m;
};

// The chromatic blur's reference wavelength that wave_psf_reach_deg takes its 380 / 575 from.
constexpr double kBlurReferenceNm = 575.0;

// The control condition has no glare: its PSF is the identity of convolution, a unit pixel at the
// centre, on the grid and angular scale the glare PSF would have.
Psf delta_psf(const PsfOptions& options) {
  Psf psf;
  psf.size_px = options.grid_px;
  psf.channels = options.spectral ? 3 : 1;
  psf.degrees_per_pixel = psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm);
  psf.values.assign(static_cast<std::size_t>(psf.channels) * psf.size_px * psf.size_px, 0.0);
  for (int c = 0; c < psf.channels; ++c) psf.at(c, psf.size_px / 2, psf.size_px / 2) = 1.0;
  return psf;
}

constexpr int kLargestGridPx = 8192;  // the largest --grid

std::string text(double value) {
  std::ostringstream out;
  out.precision(4);
  out << value;
  return out.str();
}

// Refuses a pupil the grid cannot hold or whose PSF it cannot sample, and a defocus no grid can
// sample; warns where the PSF is computed but its core crowds the grid. The numbers are those of
// docs/GLARE_OPTICS.md "Grid limits".
void check_grid(const ApertureGeometry& geometry, const PsfOptions& options, const std::string& pupil_source) {
  const SourceLocation where{"psf", 0, 0};
  const double pupil_mm = geometry.pupil_diameter_mm, width_mm = options.aperture_width_mm;
  const double pixel_mm = width_mm / options.grid_px;
  if (pupil_mm > width_mm)
    throw ConfigError(where, "--aperture-width-mm",
                      "the pupil (" + text(pupil_mm) + " mm, from " + pupil_source + ") is wider than the aperture grid (" +
                          text(width_mm) + " mm): the grid would cut it to a square, and a grid all inside the "
                          "pupil gives a point PSF; use --aperture-width-mm of at least " + text(2.0 * pupil_mm) +
                          " (twice the pupil samples the PSF's intensity without aliasing)");
  const double core_px = airy_core_diameter_px(pupil_mm, width_mm);
  if (core_px > options.grid_px)
    throw ConfigError(where, "--aperture-width-mm",
                      "the pupil (" + text(pupil_mm) + " mm) spans " + text(pupil_mm / pixel_mm) + " of the " +
                          std::to_string(options.grid_px) + " pixels across " + text(width_mm) +
                          " mm: its PSF's core (the Airy disc, 2.44 lambda / D) would be " + text(core_px) +
                          " px wide, wider than the grid; use --aperture-width-mm of at most " +
                          text(options.grid_px * pupil_mm / 2.44));
  if (core_px > 0.25 * options.grid_px)
    std::cerr << "warning: the PSF's core (the Airy disc of the " << text(pupil_mm) << " mm pupil) is " << text(core_px)
              << " px wide, more than a quarter of the " << options.grid_px
              << " px grid: its rings wrap around the grid's edges (the DFT is periodic); a smaller "
                 "--aperture-width-mm or a larger --grid narrows it\n";
  if (options.phase == PhaseForm::defocus && geometry.defocus_dioptres != 0.0) {
    const double radius_mm = 0.5 * pupil_mm;
    const double largest_grid_limit_dioptres =
        max_sampled_defocus_dioptres(options.wavelength_nm, radius_mm, width_mm / kLargestGridPx);
    if (std::abs(geometry.defocus_dioptres) > largest_grid_limit_dioptres) {
      const PhaseSamplingReport report =
          check_phase_sampling(phase_coefficient_per_m2(options.phase, options.wavelength_nm, geometry.defocus_dioptres),
                               radius_mm, pixel_mm, width_mm);
      throw ConfigError(where, "--defocus-dioptres",
                        text(geometry.defocus_dioptres) + " D needs a grid of " + text(report.required_grid_px_exact) +
                            " px over " + text(width_mm) + " mm to sample its phase at the edge of the " +
                            text(pupil_mm) + " mm pupil (less than pi per pixel at " + text(options.wavelength_nm) +
                            " nm); the largest grid, " + std::to_string(kLargestGridPx) + ", samples at most " +
                            text(largest_grid_limit_dioptres) + " D there, and --grid " +
                            std::to_string(options.grid_px) + " at most " +
                            text(max_sampled_defocus_dioptres(options.wavelength_nm, radius_mm, pixel_mm)) + " D");
    }
  }
}

const SourceLocation kWhere{"psf", 0, 0};

// The observer's refraction set on the command line: the options that make it and what it gives.
struct ObserverRefraction {
  bool active = false;
  std::string flags;  // the refraction options given, for messages ("--sphere-dioptres, --axis-deg")
  FixationRefraction fixation;
  DioptricPower ocular_refraction;
  std::string summary;  // printed once every refusal is past
};

// The wavelengths whose phase the PSF computes, and each one's power error: one for a monochromatic
// PSF; with --spectral, Ritschel's samples with the eye's LCA (glare/wave/chromatic_psf.h).
std::vector<std::pair<double, DioptricPower>> errors_by_wavelength(const ApertureGeometry& geometry,
                                                                   const PsfOptions& options) {
  if (!options.spectral) return {{options.wavelength_nm, geometry.total_power_error()}};
  ChromaticPsfOptions chromatic;
  chromatic.reference_wavelength_nm = options.wavelength_nm;
  std::vector<std::pair<double, DioptricPower>> errors;
  for (const SpectralSample& sample : spectral_samples(options.wavelength_samples))
    errors.push_back({sample.wavelength_nm, chromatic_power_error(geometry.total_power_error(), sample.wavelength_nm, chromatic)});
  return errors;
}

// check_grid's defocus refusal for the refraction's sphero-cylindrical phase: the phase of its
// strongest meridian (glare/refraction/astigmatic_phase.h) at every wavelength computed must be sampled by the
// largest grid, else no grid the program has can take it.
void check_refraction_sampling(const ApertureGeometry& geometry, const PsfOptions& options, const std::string& flags) {
  const double radius_mm = 0.5 * geometry.pupil_diameter_mm, width_mm = options.aperture_width_mm;
  for (const auto& [wavelength_nm, error] : errors_by_wavelength(geometry, options)) {
    const PhaseSamplingReport largest = check_power_error_sampling(error, wavelength_nm, radius_mm, width_mm / kLargestGridPx, width_mm);
    if (!largest.aliased) continue;
    const PrincipalPowers principal = principal_powers(error);
    const PhaseSamplingReport chosen =
        check_power_error_sampling(error, wavelength_nm, radius_mm, width_mm / options.grid_px, width_mm);
    throw ConfigError(kWhere, flags,
                      "the residual refraction error at the retina, principal powers " + text(principal.p1_dioptres) +
                          " and " + text(principal.p2_dioptres) + " D at " + text(wavelength_nm) +
                          " nm, needs a grid of " + text(chosen.required_grid_px_exact) + " px over " + text(width_mm) +
                          " mm to sample its phase at the edge of the " + text(geometry.pupil_diameter_mm) +
                          " mm pupil (less than pi per pixel); the largest grid, " + std::to_string(kLargestGridPx) +
                          ", samples at most " +
                          text(max_sampled_defocus_dioptres(wavelength_nm, radius_mm, width_mm / kLargestGridPx)) +
                          " D there, and --grid " + std::to_string(options.grid_px) + " at most " +
                          text(max_sampled_defocus_dioptres(wavelength_nm, radius_mm, width_mm / options.grid_px)) + " D");
  }
}

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

BlurEllipse geometry_blur(const ApertureGeometry& geometry) {
  return geometric_blur_ellipse(geometry.total_power_error(), 0.5e-3 * geometry.pupil_diameter_mm);
}

// The PSF of an eye with a refraction on the CPU in double: the astigmatic phase (glare/cpu/psf.h); with
// --spectral, one FFT per wavelength with the eye's LCA (glare/wave/chromatic_psf.h) instead of the scaled
// reference PSF, which only holds for a phase that does not depend on wavelength.
Psf refraction_psf(const ApertureGeometry& geometry, const PsfOptions& options, std::string& warning) {
  ApertureRasterOptions raster;
  raster.grid_px = options.grid_px;
  raster.aperture_width_mm = options.aperture_width_mm;
  raster.supersampling = options.supersampling;
  if (!options.spectral) {
    MonochromaticPsfOptions mono;
    mono.raster = raster;
    mono.wavelength_nm = options.wavelength_nm;
    mono.phase = options.phase;
    MonochromaticPsfResult result = compute_monochromatic_psf(geometry, mono);
    warning = result.sampling_warning;
    return std::move(result.psf);
  }
  ChromaticPsfOptions chromatic;
  chromatic.raster = raster;
  chromatic.reference_wavelength_nm = options.wavelength_nm;
  chromatic.wavelength_samples = options.wavelength_samples;
  ChromaticPsfResult result = compute_chromatic_psf(geometry, chromatic);
  if (!result.sampling_warning.empty())
    warning = result.sampling_warning + "; " + std::to_string(result.aliased_wavelengths) + " of " +
              std::to_string(options.wavelength_samples) + " wavelengths aliased";
  std::cout << "psf: longitudinal chromatic aberration (Thibos et al. 1992) relative to " << text(options.wavelength_nm)
            << " nm: " << text(chromatic_power_excess_dioptres(380.0, options.wavelength_nm)) << " D at 380 nm, "
            << text(chromatic_power_excess_dioptres(770.0, options.wavelength_nm)) << " D at 770 nm\n";
  return std::move(result.spectral.psf);
}

std::string prescription_text(const SpheroCylinder& rx) {
  return text(rx.sphere_dioptres) + " / " + text(rx.cylinder_dioptres) + " x " + text(rx.axis_deg);
}

// The angle the wave-optics PSF image holds in every channel: the chromatic blur's reach
// (glare/analytic/hybrid_psf.h, its 380 nm copy on the grid) for a spectral PSF, else half the grid less one pixel.
double wave_reach_deg(const PsfOptions& options) {
  const double dpp = psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm);
  if (!options.spectral) return (0.5 * options.grid_px - 1.0) * dpp;
  // wave_psf_reach_deg scales by 380 / 575: give it the degrees per pixel at 575 nm, so the reach
  // is (N/2 - 1) 380 nm / width whatever --wavelength-nm names as the reference.
  return wave_psf_reach_deg(options.grid_px, dpp * kBlurReferenceNm / options.wavelength_nm);
}

AnalyticPsf analytic_model(GlareModel model, const PsfArguments& args) {
  const ObserverEye eye{args.age_years, args.pigmentation};
  // The adaptation luminance only picks the mixture of the adaptive regime, which psf does not offer.
  if (model == GlareModel::spencer) return AnalyticPsf::spencer(parse_spencer_regime(args.regime), 1.0, eye);
  return AnalyticPsf::cie(eye);
}

// An option the chosen model does not use is refused rather than ignored: a --pigmentation given
// to Spencer's PSF (which has none) would otherwise look like it made a difference.
struct ModelOption {
  const CLI::Option* option;
  bool applies;
  const char* to;
};
void refuse_unused_options(const std::vector<ModelOption>& options, const std::string& model) {
  for (const ModelOption& entry : options)
    if (entry.option->count() > 0 && !entry.applies)
      throw ConfigError(kWhere, entry.option->get_name(), std::string("applies to ") + entry.to + ", not to --model " + model);
}

void write_profile(const std::string& path, const std::vector<ProfilePoint>& points) {
  if (path.empty()) return;
  write_profile_csv(path, points);
  std::cout << "psf: wrote " << path << ": " << points.size() << " angles from "
            << (points.empty() ? 0.0 : points.front().angle_deg) << " to " << (points.empty() ? 0.0 : points.back().angle_deg)
            << " deg\n";
}

// The analytic profile at every angle of the CSV, exactly (AnalyticPsf::profile_per_sr).
std::vector<ProfilePoint> analytic_profile(const AnalyticPsf& psf) {
  std::vector<ProfilePoint> points;
  for (double angle : profile_angles_deg()) points.push_back({angle, psf.profile_per_sr(angle)});
  return points;
}

}  // namespace

Action add_psf_command(CLI::App& app) {
  auto args = std::make_shared<PsfArguments>();
  CLI::App* command = app.add_subcommand("psf", "Compute the eye's point-spread function and write it as EXR");
  command->add_option("--pupil-diameter-mm", args->pupil_diameter_mm, "Pupil diameter (mm)")->check(finite_number_in(0.5, 12.0, "mm"))->capture_default_str();
  command->add_option("--wavelength-nm", args->wavelength_nm,
                                     "One wavelength (nm): a one-channel Y PSF; with --spectral, the reference wavelength")
                         ->check(finite_number_in(300.0, 900.0, "nm"))->capture_default_str();
  command->add_flag("--spectral", args->spectral, "Spectral PSF in linear Rec.709 R,G,B (chromatic blur, CIE 1931 weights)");
  command->add_option("--wavelength-samples", args->wavelength_samples, "Wavelength samples over 380-770 nm for --spectral")
      ->check(CLI::Range(1, 1024))->capture_default_str();
  command->add_option("--grid", args->grid_px,
                      "Aperture and PSF grid size N (even); for spencer, cie and hybrid also the side of the image "
                      "written, at --degrees-per-pixel")
      ->check(CLI::Range(16, 8192))
      ->check(CLI::Validator([](const std::string& text) {
                               // The grid's centre pixel N/2 is the optical axis and the PSF's DC.
                               try {
                                 return std::stoi(text) % 2 == 0 ? std::string() : std::string("must be even");
                               } catch (const std::exception&) {
                                 return std::string("must be an even integer");
                               }
                             },
                             "EVEN"))
      ->capture_default_str();
  command->add_option("--aperture-width-mm", args->aperture_width_mm, "Side of the square aperture grid (mm)")
      ->check(finite_positive_number("mm"))->capture_default_str();
  command->add_option("--supersampling", args->supersampling, "Sub-samples per pixel side (>= 2)")->check(CLI::Range(2, 16))->capture_default_str();
  command->add_option("--fresnel", args->fresnel, "Phase before the FFT: none (Fraunhofer), defocus, paper (Eq. 3, d = 24 mm)")
      ->check(CLI::IsMember({"none", "defocus", "paper"}))->capture_default_str();
  CLI::Option* pupil_option = command->get_option("--pupil-diameter-mm");
  CLI::Option* defocus_option =
      command->add_option("--defocus-dioptres", args->defocus_dioptres,
                          "Accommodation error (dioptres) for --fresnel defocus (with --mode: replaces the eye's)")
          ->check(finite_number())
          ->capture_default_str();
  command->add_option("--backend", args->backend, "Compute backend: cpu (FFTW double), gl, or auto (gl on a hardware GPU)")
      ->check(CLI::IsMember({"cpu", "gl", "auto"}))->capture_default_str();
  CLI::Option* gratings_option = command->add_flag(
      "--gratings", args->gratings, "Add radial lens-fibre gratings (annulus 1.5-2.5 mm, halo at 3 deg for 568 nm)");
  CLI::Option* mode_option =
      command->add_option("--mode", args->mode,
                          "Aperture from the eye model (docs/EYE_MODEL.md) in this condition: dynamic, static (frozen "
                          "at the eye's static time), control (no glare: a delta PSF)")
          ->check(CLI::IsMember({"dynamic", "static", "control"}))
          ->excludes(gratings_option);
  command->add_option("--time-s", args->time_s, "Time of the eye model (s), at most 86400 (24 h)")
      ->check(eye_model_time_s())
      ->needs(mode_option)
      ->capture_default_str();
  command->add_option("--seed", args->seed, "Seed of the eye model")->check(seed_check())->needs(mode_option)->capture_default_str();
  command->add_option("--components", args->components,
                      "Parts of the eye to keep, comma-separated: pupil,lens,gratings,vitreous,cornea,retina,lashes, or all")
      ->needs(mode_option)
      ->check(CLI::Validator(
          [](const std::string& text) {
            try {
              parse_component_selection(text);
              return std::string();
            } catch (const std::invalid_argument& error) {
              return std::string(error.what());
            }
          },
          "COMPONENTS"))
      ->capture_default_str();
  command->add_option("--model", args->model,
                          "Glare model: ritschel (the wave-optics eye above), spencer (Spencer et al. 1995), cie (CIE "
                          "146:2002), hybrid (the wave-optics eye near the source, an analytic far field beyond)")
          ->check(CLI::IsMember({"ritschel", "spencer", "cie", "hybrid"}))
          ->capture_default_str();
  CLI::Option* regime_option =
      command->add_option("--regime", args->regime, "Spencer's mixture: photopic (Eq. 5), mesopic (Eq. 8), scotopic (Eq. 9)")
          ->check(CLI::IsMember({"photopic", "mesopic", "scotopic"}))
          ->capture_default_str();
  CLI::Option* age_option =
      command->add_option("--age-years", args->age_years, "Observer's age (years): Spencer Eq. 10, CIE 146, and with a refraction flag the accommodation "
                          "amplitude (Hofstetter 1950: 18.5 - 0.3 age D)")
          ->check(finite_number_in(1.0, 100.0, "years"))
          ->capture_default_str();
  CLI::Option* pigmentation_option =
      command->add_option("--pigmentation", args->pigmentation,
                          "CIE 146 eye pigmentation: 0 very dark eyes, 0.5 brown, 1 blue-green")
          ->check(finite_number_in(0.0, 1.0, ""))
          ->capture_default_str();
  CLI::Option* far_field_option =
      command->add_option("--far-field", args->far_field, "The hybrid's analytic far field: spencer or cie")
          ->check(CLI::IsMember({"spencer", "cie"}))
          ->capture_default_str();
  CLI::Option* handover_option =
      command->add_option("--handover-deg", args->handover_deg,
                          "The hybrid's hand-over annulus INNER,OUTER (degrees from the source; default: from half of 0.9 "
                          "to 0.9 of the wave PSF's reach, which the outer angle must not pass)")
          ->delimiter(',')
          ->expected(2)
          ->check(finite_positive_number("deg"));
  CLI::Option* dpp_option =
      command->add_option("--degrees-per-pixel", args->degrees_per_pixel,
                          "Angle of the image's centre pixel for spencer, cie and hybrid (a flat display whose pixel "
                          "subtends it at the line of sight)")
          ->check(finite_number_in(1e-4, 2.0, "deg"))
          ->capture_default_str();
  command->add_option("--profile-csv", args->profile_csv,
                      "Also write the radial profile (angle_deg,psf_per_sr) at log-spaced angles from 0.01 to 90 deg, "
                      "20 or more per decade. spencer: the whole P of Eq. 5/8/9 with the halo at 568 nm; cie: the CIE "
                      "formula (the scattered light); ritschel, hybrid: the azimuthal mean of the image's pixel "
                      "densities (value / solid angle; R,G,B by Rec.709 luminance weights) on 1-pixel rings, at the "
                      "angles the image reaches")
      ->check(file_extension_in({".csv"}, "the profile file"));
  // EXR only: the PSF is linear data summing to 1, which an 8-bit PNG would round to nothing.
  command->add_option("--out", args->out,
                      "Output EXR file (unit sum per channel; for spencer, cie and hybrid the sum counts only the "
                      "light within the image). --out, --profile-csv or both.")
      ->check(file_extension_in({".exr"}, "the PSF file"));
  // The observer's refraction (glare/refraction/eye_refraction.h, docs/REFRACTION.md).
  CLI::Option* sphere_option =
      command->add_option("--sphere-dioptres", args->sphere_dioptres,
                          "The eye's refractive error as its correcting prescription: sphere (dioptres, at "
                          "--vertex-distance-mm)")
          ->check(finite_number_in(-kMaxSphereDioptres, kMaxSphereDioptres, "D"));
  CLI::Option* cylinder_option =
      command->add_option("--cylinder-dioptres", args->cylinder_dioptres,
                          "The correcting prescription's cylinder (dioptres; minus-cylinder form, a plus cylinder is "
                          "transposed and said so)")
          ->check(finite_number_in(-kMaxCylinderDioptres, kMaxCylinderDioptres, "D"));
  CLI::Option* axis_option =
      command->add_option("--axis-deg", args->axis_deg, "The correcting prescription's cylinder axis (TABO degrees, 0-180)")
          ->check(finite_number_in(0.0, kMaxAxisDeg, "deg"))
          ->needs(cylinder_option);
  CLI::Option* spectacles_option =
      command->add_option("--spectacles", args->spectacles,
                          "Spectacle lenses worn, SPHERE,CYLINDER,AXIS (dioptres, dioptres, TABO degrees) at "
                          "--vertex-distance-mm")
          ->check(sphero_cylinder_check());
  CLI::Option* viewing_option =
      command->add_option("--viewing-distance-m", args->viewing_distance_m,
                          "Distance of the fixated point source from the cornea (m; default: infinity)")
          ->check(finite_positive_number("m"));
  CLI::Option* amplitude_option =
      command->add_option("--accommodation-amplitude-dioptres", args->accommodation_amplitude_dioptres,
                          "Amplitude of accommodation (dioptres; default: Table 2's 11.93, or from --age-years by "
                          "Hofstetter 1950)")
          ->check(finite_number_in(0.0, 20.0, "D"))
          ->excludes(age_option);
  CLI::Option* vertex_option =
      command->add_option("--vertex-distance-mm", args->vertex_distance_mm,
                          "Vertex distance of the prescription and of --spectacles (mm)")
          ->check(finite_number_in(0.0, 40.0, "mm"))
          ->capture_default_str();
  const std::vector<CLI::Option*> refraction_options = {sphere_option,   cylinder_option, axis_option,   spectacles_option,
                                                        viewing_option, amplitude_option, vertex_option};
  std::vector<const CLI::Option*> wave_options;
  for (const char* name : {"--pupil-diameter-mm", "--wavelength-nm", "--spectral", "--wavelength-samples",
                           "--aperture-width-mm", "--supersampling", "--fresnel", "--defocus-dioptres", "--backend",
                           "--gratings", "--mode", "--time-s", "--seed", "--components"})
    wave_options.push_back(command->get_option(name));
  for (const CLI::Option* option : refraction_options) wave_options.push_back(option);
  return [=]() {
    return report_errors([&]() {
      if (args->out.empty() && args->profile_csv.empty())
        throw ConfigError({"--out", 0, 0}, "out", "nothing to write: give --out FILE.exr, --profile-csv FILE.csv or both");
      const GlareModel model = parse_glare_model(args->model);
      const bool analytic = model == GlareModel::spencer || model == GlareModel::cie;
      const GlareModel far_model = model == GlareModel::hybrid ? parse_glare_model(args->far_field) : model;
      ObserverRefraction refraction;
      for (const CLI::Option* option : refraction_options)
        if (option->count() > 0) {
          refraction.active = true;
          refraction.flags += (refraction.flags.empty() ? "" : ", ") + option->get_name();
        }
      std::vector<ModelOption> checks = {
          {age_option, model != GlareModel::ritschel || refraction.active,
           "the analytic models (--model spencer, cie or hybrid) and the observer's refraction (--sphere-dioptres, "
           "--cylinder-dioptres, --spectacles, --viewing-distance-m, ...)"},
          {regime_option, far_model == GlareModel::spencer, "Spencer's PSF (--model spencer, or hybrid with --far-field spencer)"},
          // --age-years also sets the refraction's accommodation amplitude, so it applies to every model.
          {pigmentation_option, far_model == GlareModel::cie, "the CIE PSF (--model cie, or hybrid with --far-field cie)"},
          {far_field_option, model == GlareModel::hybrid, "--model hybrid"},
          {handover_option, model == GlareModel::hybrid, "--model hybrid"},
          {dpp_option, model != GlareModel::ritschel, "the images of --model spencer, cie and hybrid"}};
      for (const CLI::Option* option : wave_options)
        checks.push_back({option, !analytic, "the wave-optics eye (--model ritschel or hybrid)"});
      refuse_unused_options(checks, args->model);
      if (analytic) {
        // --grid must be even already; the image is the analytic kernel on a flat display.
        const AnalyticPsf psf = analytic_model(model, *args);
        if (!args->out.empty()) {
          const Psf image = analytic_psf_image(psf, args->degrees_per_pixel, args->grid_px);
          write_psf_exr(args->out, image);
          std::cout << "psf: wrote " << args->out << ": " << args->model << " (age " << args->age_years << " years"
                    << (model == GlareModel::spencer ? ", " + args->regime : ", pigmentation " + text(args->pigmentation))
                    << "), " << image.size_px << "x" << image.size_px << " px, " << (image.channels == 1 ? "Y" : "R,G,B")
                    << ", " << image.degrees_per_pixel << " deg/px at the centre, unit sum within the image\n";
        }
        write_profile(args->profile_csv, analytic_profile(psf));
        return 0;
      }
      ApertureGeometry geometry;
      geometry.pupil_diameter_mm = args->pupil_diameter_mm;
      geometry.defocus_dioptres = args->defocus_dioptres;
      if (!args->mode.empty()) {
        EyeParameters parameters;
        parameters.mode = parse_glare_mode(args->mode);
        geometry = keep_components(EyeModel(parameters, args->seed).geometry_at(args->time_s),
                                   parse_component_selection(args->components));
        if (pupil_option->count() > 0) geometry.pupil_diameter_mm = args->pupil_diameter_mm;
        if (defocus_option->count() > 0) geometry.defocus_dioptres = args->defocus_dioptres;
        std::cout << "psf: eye model " << args->mode << ", t " << args->time_s << " s, seed " << args->seed << ": pupil "
                  << geometry.pupil_diameter_mm << " mm, defocus " << geometry.defocus_dioptres << " D, "
                  << geometry.discs.size() << " discs, " << geometry.lines.size() << " lines, "
                  << geometry.polygons.size() << " polygons (" << args->components << ")\n";
      }
      if (args->gratings) {
        FibreGratingOptions gratings;
        gratings.period_um = grating_period_um(568.0, 3.0);
        add_radial_fibre_gratings(geometry, gratings);
        // A grating finer than two aperture pixels aliases; the halo is then wrong (docs/GLARE_OPTICS.md).
        const double pixel_um = 1e3 * args->aperture_width_mm / args->grid_px;
        if (pixel_um > 0.5 * gratings.period_um)
          std::cerr << "warning: fibre gratings of period " << gratings.period_um << " um are not resolved by "
                    << pixel_um << " um aperture pixels (need < " << 0.5 * gratings.period_um
                    << " um: e.g. --grid 2048 --aperture-width-mm 5.6)\n";
      }
      if (refraction.active) {
        // The eye's error, the lenses worn and the fixation distance give the residual error E at the
        // retina (glare/refraction/eye_refraction.h), the pupil phase's sphero-cylindrical part.
        if (cylinder_option->count() > 0 && args->cylinder_dioptres != 0.0 && axis_option->count() == 0)
          throw ConfigError(kWhere, "--axis-deg", "a cylinder needs its axis (TABO degrees, 0 to 180)");
        if (args->fresnel != "defocus")
          throw ConfigError(kWhere, "--fresnel",
                            "the observer's refraction (" + refraction.flags + ") is a defocus phase; it needs --fresnel defocus");
        if (args->backend == "gl")
          throw ConfigError(kWhere, "--backend",
                            "the observer's refraction (" + refraction.flags +
                                ": an astigmatic phase and, with --spectral, one FFT per wavelength) is computed on the "
                                "CPU; use --backend cpu or auto");
        const SpheroCylinder written{args->sphere_dioptres, args->cylinder_dioptres, args->axis_deg};
        const double vertex_m = 1e-3 * args->vertex_distance_mm;
        EyeRefraction eye_refraction;
        eye_refraction.correcting_prescription = minus_cylinder_form(written);
        eye_refraction.prescription_vertex_distance_m = vertex_m;
        if (args->cylinder_dioptres > 0.0)
          std::cerr << "psf: the prescription " << prescription_text(written)
                    << " has a plus cylinder; taken as its minus-cylinder transposition "
                    << prescription_text(eye_refraction.correcting_prescription) << "\n";
        eye_refraction.accommodation_amplitude_dioptres =
            amplitude_option->count() > 0 ? args->accommodation_amplitude_dioptres
            : age_option->count() > 0     ? hofstetter_amplitude_dioptres(args->age_years)
                                          : kSchematicAccommodationAmplitudeDioptres;
        ViewingCondition viewing;
        viewing.fixation_distance_m = args->viewing_distance_m;
        if (!args->spectacles.empty()) {
          const SpheroCylinder lens = parse_sphero_cylinder(args->spectacles);
          viewing.spectacles = ThinSpectacleLens{minus_cylinder_form(lens), vertex_m};
          if (lens.cylinder_dioptres > 0.0)
            std::cerr << "psf: --spectacles " << prescription_text(lens)
                      << " has a plus cylinder; taken as its minus-cylinder transposition "
                      << prescription_text(viewing.spectacles->prescription) << "\n";
          if (!(viewing.fixation_distance_m > vertex_m))
            throw ConfigError(kWhere, "--viewing-distance-m",
                              "the fixated point (" + text(viewing.fixation_distance_m) +
                                  " m from the cornea) must lie beyond the spectacles (" + text(args->vertex_distance_mm) +
                                  " mm)");
        }
        try {
          const RefractiveEye eye(eye_refraction);
          refraction.ocular_refraction = eye.ocular_refraction();
          refraction.fixation = refraction_at_fixation(eye, viewing);
        } catch (const std::invalid_argument& error) {
          throw ConfigError(kWhere, refraction.flags, error.what());
        }
        geometry.refraction_error = refraction.fixation.residual;
        const BlurEllipse blur = geometry_blur(geometry);
        std::ostringstream summary;
        summary << "psf: refraction: ocular refraction at the cornea "
                  << prescription_text(refraction.ocular_refraction.prescription()) << " D, amplitude "
                  << text(eye_refraction.accommodation_amplitude_dioptres) << " D, accommodation "
                  << text(refraction.fixation.accommodation_dioptres) << " D for the point at "
                  << (std::isinf(viewing.fixation_distance_m) ? std::string("infinity") : text(viewing.fixation_distance_m) + " m")
                  << "; residual at the retina "
                  << prescription_text(refraction.fixation.residual.prescription())
                  << " D (positive: too much power); geometric blur " << text(2.0 * blur.semi_major_rad * kDegPerRad)
                  << " x " << text(2.0 * blur.semi_minor_rad * kDegPerRad) << " deg, major axis at "
                  << text(blur.major_axis_angle_deg) << " deg from the observer's right, counterclockwise\n";
        refraction.summary = summary.str();
      }
      PsfOptions options;
      options.grid_px = args->grid_px;
      options.aperture_width_mm = args->aperture_width_mm;
      options.supersampling = args->supersampling;
      options.wavelength_nm = args->wavelength_nm;
      options.spectral = args->spectral;
      options.wavelength_samples = args->wavelength_samples;
      options.phase = parse_phase_form(args->fresnel);
      check_grid(geometry, options,
                 args->mode.empty() || pupil_option->count() > 0 ? "--pupil-diameter-mm" : "the eye model at --time-s");
      if (refraction.active) check_refraction_sampling(geometry, options, refraction.flags);
      const double reach_deg = wave_reach_deg(options);
      HybridHandover handover;
      if (model == GlareModel::hybrid) {
        // Everything the hybrid can refuse is refused here, before any PSF is computed.
        try {
          check_psf_fits_display(options.grid_px, psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm),
                                 args->degrees_per_pixel);
        } catch (const PsfScaleError& error) {
          throw ConfigError(kWhere, "--degrees-per-pixel", error.what());
        }
        handover = args->handover_deg.empty() ? default_handover(reach_deg)
                                              : HybridHandover{args->handover_deg[0], args->handover_deg[1]};
        try {
          check_handover(handover, reach_deg);
        } catch (const HandoverError& error) {
          throw ConfigError(kWhere, "--handover-deg", std::string(error.what()) + " (--grid " +
                                                          std::to_string(options.grid_px) + ", --aperture-width-mm " +
                                                          text(options.aperture_width_mm) + ")");
        }
      }
      std::cout << refraction.summary;
      std::unique_ptr<GlareBackend> backend;
      std::string backend_name = "cpu float64";
      if (refraction.active) {
        std::cout << "psf: cpu float64: the observer's refraction is computed on the CPU (its astigmatic phase"
                  << (options.spectral ? ", and one FFT per wavelength with the eye's longitudinal chromatic aberration)\n"
                                       : ")\n");
      } else {
        GlareBackendChoice choice = create_glare_backend(args->backend, {.gl_context = gl::compute_context_factory()});
        std::cout << "psf: " << choice.reason << "\n";
        backend = std::move(choice.backend);
        backend_name = backend->name();
      }
      Psf psf;
      if (!geometry.glare_enabled) {
        psf = delta_psf(options);
        std::cout << "psf: control condition: no glare, a delta PSF (the image passes through unchanged)\n";
      } else {
        std::string warning;
        try {
          if (backend) {
            psf = backend->psf(geometry, options);
            warning = backend->last_warning();
          } else {
            psf = refraction_psf(geometry, options, warning);
          }
        } catch (const ClosedApertureError& error) {
          // A closed eye (a blink at --time-s, or only lids kept) lets no light through: no PSF exists.
          throw ConfigError({"psf", 0, 0}, args->mode.empty() ? "--pupil-diameter-mm" : "--time-s",
                            std::string("no light passes the aperture, so there is no PSF (") + error.what() + ")");
        }
        if (!warning.empty()) std::cerr << "warning: " << warning << "\n";
      }
      if (model == GlareModel::hybrid) {
        const Psf wave_display = resample_psf_to_display(psf, args->degrees_per_pixel);
        const DisplayGeometry display = flat_display_geometry(args->degrees_per_pixel);
        const AnalyticPsf far_psf = analytic_model(far_model, *args);
        const int half = args->grid_px / 2;
        const DisplayKernel kernel = analytic_display_kernel(far_psf, display, half, half, 2);
        const HandoverPixels handover_px = handover_pixels(handover, display);
        Psf near;
        try {
          near = hybrid_near_psf(wave_display, analytic_energy_inside(kernel, handover_px), handover_px);
        } catch (const HandoverError& error) {
          throw ConfigError(kWhere, "--handover-deg", error.what());
        }
        const Psf image = hybrid_psf_image(near, hybrid_far_kernel(kernel, handover_px), args->degrees_per_pixel, args->grid_px);
        if (!args->out.empty()) write_psf_exr(args->out, image);
        if (!args->out.empty()) std::cout << "psf: wrote " << args->out << ": hybrid, the wave-optics eye to " << handover.inner_deg
                  << " deg, blended into " << args->far_field << " (age " << args->age_years << " years) by "
                  << handover.outer_deg << " deg; " << image.size_px << "x" << image.size_px << " px, R,G,B, "
                  << image.degrees_per_pixel << " deg/px at the centre, unit sum within the image\n";
        // The image holds near + far out to its edge: its reach is the image's (half its side less a pixel).
        write_profile(args->profile_csv,
                      image_profile_per_sr(image, PixelLayout::flat_display, profile_angles_deg(), kProfileLastAngleDeg));
        return 0;
      }
      if (!args->out.empty()) write_psf_exr(args->out, psf);
      if (!args->out.empty()) std::cout << "psf: wrote " << args->out << ": " << psf.size_px << "x" << psf.size_px << " px, "
                << (psf.channels == 1 ? "Y" : "R,G,B") << ", " << psf.degrees_per_pixel << " deg/px, pupil "
                << geometry.pupil_diameter_mm << " mm, fresnel " << args->fresnel << ", backend " << backend_name << "\n";
      write_profile(args->profile_csv, image_profile_per_sr(psf, PixelLayout::uniform_angle, profile_angles_deg(), reach_deg));
      return 0;
    });
  };
}

}  // namespace glarelab::cli
