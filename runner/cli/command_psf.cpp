// glarelab psf: the eye's point-spread function (the human eye of sessions by default; Ritschel et
// al. 2009's wave-optics eye, with the observer's refraction of runner/cli/psf_refraction.h), or
// Spencer's, the CIE's or the hybrid's kernel, written as EXR and as a radial profile. The wave-optics
// PSF is computed by what a frame engine chooses for --backend (stimuli/frame_engine.h,
// engine_glare_backend; cpu, the float64 reference, by default).
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "glare/analytic/analytic_psf.h"
#include "glare/eye/aperture_components.h"
#include "glare/refraction/chromatic_eye.h"
#include "glare/analytic/display_psf_image.h"
#include "glare/eye/eye_model.h"
#include "glare/eye/fibre_gratings.h"
#include "glare/glare_backend.h"
#include "glare/analytic/hybrid_psf.h"
#include "glare/analytic/spencer_flare_lines.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_exr.h"
#include "glare/wave/psf_profile.h"
#include "glare/wave/psf_scale.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "runner/cli/commands.h"
#include "runner/cli/command_psf_eye.h"
#include "runner/cli/command_psf_luidolt.h"
#include "runner/cli/option_checks.h"
#include "runner/cli/psf_options.h"
#include "runner/cli/psf_refraction.h"
#include "runner/display/compute_context.h"
#include "stimuli/frame_engine.h"

namespace glarelab::cli {
namespace {

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

const SourceLocation kWhere{"psf", 0, 0};

// Refuses a pupil the grid cannot hold or whose PSF it cannot sample, and a defocus no grid can
// sample; warns where the PSF is computed but its core crowds the grid. The numbers are those of
// docs/GLARE_OPTICS.md "Grid limits".
void check_grid(const ApertureGeometry& geometry, const PsfOptions& options, const std::string& pupil_source) {
  const SourceLocation where{"psf", 0, 0};
  const double pupil_mm = geometry.pupil_diameter_mm, width_mm = options.aperture_width_mm;
  const double pixel_mm = width_mm / options.grid_px;
  if (pupil_mm > width_mm)
    throw ConfigError(where, "--aperture-width-mm",
                      "the pupil (" + psf_text(pupil_mm) + " mm, from " + pupil_source + ") is wider than the aperture grid (" +
                          psf_text(width_mm) + " mm): the grid would cut it to a square, and a grid all inside the "
                          "pupil gives a point PSF; use --aperture-width-mm of at least " + psf_text(2.0 * pupil_mm) +
                          " (twice the pupil samples the PSF's intensity without aliasing)");
  const double core_px = airy_core_diameter_px(pupil_mm, width_mm);
  if (core_px > options.grid_px)
    throw ConfigError(where, "--aperture-width-mm",
                      "the pupil (" + psf_text(pupil_mm) + " mm) spans " + psf_text(pupil_mm / pixel_mm) + " of the " +
                          std::to_string(options.grid_px) + " pixels across " + psf_text(width_mm) +
                          " mm: its PSF's core (the Airy disc, 2.44 lambda / D) would be " + psf_text(core_px) +
                          " px wide, wider than the grid; use --aperture-width-mm of at most " +
                          psf_text(options.grid_px * pupil_mm / 2.44));
  if (core_px > 0.25 * options.grid_px)
    std::cerr << "warning: the PSF's core (the Airy disc of the " << psf_text(pupil_mm) << " mm pupil) is " << psf_text(core_px)
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
                        psf_text(geometry.defocus_dioptres) + " D needs a grid of " + psf_text(report.required_grid_px_exact) +
                            " px over " + psf_text(width_mm) + " mm to sample its phase at the edge of the " +
                            psf_text(pupil_mm) + " mm pupil (less than pi per pixel at " + psf_text(options.wavelength_nm) +
                            " nm); the largest grid, " + std::to_string(kLargestGridPx) + ", samples at most " +
                            psf_text(largest_grid_limit_dioptres) + " D there, and --grid " +
                            std::to_string(options.grid_px) + " at most " +
                            psf_text(max_sampled_defocus_dioptres(options.wavelength_nm, radius_mm, pixel_mm)) + " D");
    }
  }
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

// The aperture: a bare pupil, or the eye model at --time-s (its parts as --components keeps), with
// --pupil-diameter-mm and --defocus-dioptres replacing the model's where given; --gratings adds
// radial fibre gratings.
// With the eye model, `eye` receives its parameters and the share of the light its gratings send
// into the lenticular halo through the pupil (command_psf_eye.h).
struct PsfEye {
  EyeParameters parameters;
  double halo_energy = 0.0;
};
ApertureGeometry psf_geometry(const PsfArguments& args, const PsfOptionHandles& handles, const std::string& mode,
                              PsfEye& eye) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = args.pupil_diameter_mm;
  geometry.defocus_dioptres = args.defocus_dioptres;
  if (!mode.empty()) {
    eye.parameters = psf_eye_parameters(args, mode);
    const EyeModel model(eye.parameters, args.seed);
    geometry = keep_components(model.geometry_at(args.time_s), parse_component_selection(args.components));
    if (handles.pupil->count() > 0) geometry.pupil_diameter_mm = args.pupil_diameter_mm;
    if (handles.defocus->count() > 0) geometry.defocus_dioptres = args.defocus_dioptres;
    eye.halo_energy = psf_halo_energy(model.lens().grating_lines(), geometry, eye.parameters);
    std::cout << "psf: eye model " << mode << " at " << args.field_luminance_cd_m2 << " cd/m2, t " << args.time_s << " s, seed " << args.seed << ": pupil "
              << geometry.pupil_diameter_mm << " mm, defocus " << geometry.defocus_dioptres << " D, "
              << geometry.discs.size() << " discs, " << geometry.lines.size() << " lines, "
              << geometry.polygons.size() << " polygons (" << args.components << ")"
              << (args.eye_from.empty() ? std::string() : ", [glare.eye] of " + args.eye_from) << "\n";
  }
  if (args.gratings) {
    FibreGratingOptions gratings;
    gratings.period_um = grating_period_um(568.0, 3.0);
    add_radial_fibre_gratings(geometry, gratings);
    // A grating finer than two aperture pixels aliases; the halo is then wrong (docs/GLARE_OPTICS.md).
    const double pixel_um = 1e3 * args.aperture_width_mm / args.grid_px;
    if (pixel_um > 0.5 * gratings.period_um)
      std::cerr << "warning: fibre gratings of period " << gratings.period_um << " um are not resolved by "
                << pixel_um << " um aperture pixels (need < " << 0.5 * gratings.period_um
                << " um: e.g. --grid 2048 --aperture-width-mm 5.6)\n";
  }
  return geometry;
}

// The observer's refraction when any of its options is given: refused with options it cannot take,
// else read into geometry.refraction_error (psf_refraction.h).
ObserverRefraction observer_refraction(const PsfArguments& args, const PsfOptionHandles& handles, ApertureGeometry& geometry) {
  ObserverRefraction refraction;
  for (const CLI::Option* option : handles.refraction)
    if (option->count() > 0) {
      refraction.active = true;
      refraction.flags += (refraction.flags.empty() ? "" : ", ") + option->get_name();
    }
  if (!refraction.active) return refraction;
  if (handles.cylinder->count() > 0 && args.refraction.cylinder_dioptres != 0.0 && handles.axis->count() == 0)
    throw ConfigError(kWhere, "--axis-deg", "a cylinder needs its axis (TABO degrees, 0 to 180)");
  if (args.fresnel != "defocus")
    throw ConfigError(kWhere, "--fresnel",
                      "the observer's refraction (" + refraction.flags + ") is a defocus phase; it needs --fresnel defocus");
  read_observer_refraction(args.refraction, handles.amplitude->count() > 0, handles.age->count() > 0, args.age_years,
                           refraction, geometry);
  return refraction;
}

// The hybrid's hand-over annulus; everything the hybrid can refuse is refused here, before any PSF
// is computed.
HybridHandover hybrid_handover(const PsfArguments& args, const PsfOptions& options, double reach_deg) {
  try {
    check_psf_fits_display(options.grid_px, psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm),
                           args.degrees_per_pixel);
  } catch (const PsfScaleError& error) {
    throw ConfigError(kWhere, "--degrees-per-pixel", error.what());
  }
  const HybridHandover handover = args.handover_deg.empty() ? default_handover(reach_deg)
                                                            : HybridHandover{args.handover_deg[0], args.handover_deg[1]};
  try {
    check_handover(handover, reach_deg);
  } catch (const HandoverError& error) {
    throw ConfigError(kWhere, "--handover-deg", std::string(error.what()) + " (--grid " + std::to_string(options.grid_px) +
                                                    ", --aperture-width-mm " + psf_text(options.aperture_width_mm) + ")");
  }
  return handover;
}

// The wave-optics PSF as a frame engine computes it: the compute choice of a session's frames
// (engine_glare_backend, stimuli/frame_engine.h), so that psf and sessions never choose apart.
// "cpu", psf's default, is the float64 reference; "auto" GL on a hardware GPU, else the planned
// float32 path; "gl" GL. Every one computes the observer's refraction itself. With
// `display_degrees_per_pixel` (the hybrid and human models) the spectral PSF comes at the display's
// scale as a session's frames take it; without, on the aperture grid. `backend_name` receives what
// computed it.
Psf wave_psf(const PsfArguments& args, bool backend_named, const ObserverRefraction& refraction,
             const ApertureGeometry& geometry, const PsfOptions& options, std::optional<double> display_degrees_per_pixel,
             std::string& backend_name) {
  const double grid_degrees_per_pixel = psf_degrees_per_pixel(options.wavelength_nm, options.aperture_width_mm);
  const GlareFrameLayout layout{options, display_degrees_per_pixel.value_or(grid_degrees_per_pixel)};
  const GlareBackendChoice choice =
      engine_glare_backend(args.backend, layout, gl::compute_context_factory(), backend_named);
  std::cout << "psf: " << choice.reason << "\n";
  if (refraction.active)
    std::cout << "psf: " << choice.backend->name() << " computes the observer's refraction (its astigmatic phase"
              << (options.spectral ? ", and one FFT per wavelength with the eye's longitudinal chromatic aberration)\n"
                                   : ")\n");
  backend_name = choice.backend->name();
  if (!geometry.glare_enabled) {
    std::cout << "psf: control condition: no glare, a delta PSF (the image passes through unchanged)\n";
    return display_degrees_per_pixel ? resample_psf_to_display(delta_psf(options), *display_degrees_per_pixel)
                                     : delta_psf(options);
  }
  Psf psf;
  try {
    if (!display_degrees_per_pixel) psf = choice.backend->psf(geometry, options);
    else if (options.spectral) psf = choice.backend->display_psf(geometry, options, *display_degrees_per_pixel);
    else psf = resample_psf_to_display(choice.backend->psf(geometry, options), *display_degrees_per_pixel);
  } catch (const ClosedApertureError& error) {
    // A closed eye (a blink at --time-s, or only lids kept) lets no light through: no PSF exists.
    throw ConfigError({"psf", 0, 0}, args.mode.empty() && args.model != "human" ? "--pupil-diameter-mm" : "--time-s",
                      std::string("no light passes the aperture, so there is no PSF (") + error.what() + ")");
  }
  if (refraction.active && options.spectral)
    std::cout << "psf: longitudinal chromatic aberration (Thibos et al. 1992) relative to " << psf_text(options.wavelength_nm)
              << " nm: " << psf_text(chromatic_power_excess_dioptres(380.0, options.wavelength_nm)) << " D at 380 nm, "
              << psf_text(chromatic_power_excess_dioptres(770.0, options.wavelength_nm)) << " D at 770 nm\n";
  if (const std::string warning = choice.backend->last_warning(); !warning.empty())
    std::cerr << "warning: " << warning << "\n";
  return psf;
}

// --model spencer or cie: the analytic kernel on a flat display (--grid must be even already).
int write_analytic(GlareModel model, const PsfArguments& args) {
  const AnalyticPsf psf = analytic_model(model, args);
  if (!args.out.empty()) {
    const Psf image = args.flare_lines
                          ? spencer_flare_psf_image(psf.mixture(), args.degrees_per_pixel, args.grid_px, args.flare_seed)
                          : analytic_psf_image(psf, args.degrees_per_pixel, args.grid_px);
    write_psf_exr(args.out, image);
    std::cout << "psf: wrote " << args.out << ": " << args.model << " (age " << args.age_years << " years"
              << (model == GlareModel::spencer ? ", " + args.regime : ", pigmentation " + psf_text(args.pigmentation))
              << (args.flare_lines ? ", flare lines of seed " + std::to_string(args.flare_seed) : std::string())
              << "), " << image.size_px << "x" << image.size_px << " px, " << (image.channels == 1 ? "Y" : "R,G,B")
              << ", " << image.degrees_per_pixel << " deg/px at the centre, unit sum within the image\n";
  }
  write_profile(args.profile_csv, analytic_profile(psf));
  return 0;
}

// --model hybrid: the wave PSF on the display's pixels near the source, the analytic far field beyond;
// --model human: the same join with the near part calibrated ring by ring to CIE 146 (calibrated_near_psf).
// `wave_display`: the wave-optics PSF at the display's scale (wave_psf).
int write_hybrid(const PsfArguments& args, const Psf& wave_display, const HybridHandover& handover, bool human,
                 const PsfEye& eye) {
  const DisplayGeometry display = flat_display_geometry(args.degrees_per_pixel);
  const AnalyticPsf far_psf = analytic_model(human ? GlareModel::cie : parse_glare_model(args.far_field), args);
  const int half = args.grid_px / 2;
  const DisplayKernel kernel = analytic_display_kernel(far_psf, display, half, half, 2);
  const HandoverPixels handover_px = handover_pixels(handover, display);
  Psf near;
  try {
    near = human ? calibrated_near_psf(wave_display, kernel, handover_px)
                 : hybrid_near_psf(wave_display, analytic_energy_inside(kernel, handover_px), handover_px);
  } catch (const HandoverError& error) {
    throw ConfigError(kWhere, "--handover-deg", error.what());
  }
  // The human eye's kernel carries the lenticular halo where the pupil uncovers the gratings, as a
  // session's frame does (glare/analytic/lenticular_halo.h).
  const DisplayKernel far = human ? with_lenticular_halo(hybrid_far_kernel(kernel, handover_px), eye.parameters,
                                                         eye.halo_energy, args.degrees_per_pixel)
                                  : hybrid_far_kernel(kernel, handover_px);
  if (human)
    std::cout << "psf: lenticular halo: " << psf_text(100.0 * eye.halo_energy) << " % of the light"
              << (eye.halo_energy > 0.0 ? " (the pupil uncovers the lens-fibre gratings)\n"
                                        : " (the pupil leaves the lens-fibre gratings covered)\n");
  const Psf image = hybrid_psf_image(near, far, args.degrees_per_pixel, args.grid_px);
  if (!args.out.empty()) write_psf_exr(args.out, image);
  if (!args.out.empty() && human)
    std::cout << "psf: wrote " << args.out << ": human, the wave-optics eye to " << handover.outer_deg
              << " deg at the light CIE 146 gives on every ring (age " << args.age_years << " years, pigmentation "
              << psf_text(args.pigmentation) << "), CIE beyond; " << image.size_px << "x" << image.size_px
              << " px, R,G,B, " << image.degrees_per_pixel << " deg/px at the centre, unit sum within the image\n";
  else if (!args.out.empty()) std::cout << "psf: wrote " << args.out << ": hybrid, the wave-optics eye to " << handover.inner_deg
            << " deg, blended into " << args.far_field << " (age " << args.age_years << " years) by "
            << handover.outer_deg << " deg; " << image.size_px << "x" << image.size_px << " px, R,G,B, "
            << image.degrees_per_pixel << " deg/px at the centre, unit sum within the image\n";
  // The image holds near + far out to its edge: its reach is the image's (half its side less a pixel).
  write_profile(args.profile_csv,
                image_profile_per_sr(image, PixelLayout::flat_display, profile_angles_deg(), kProfileLastAngleDeg));
  return 0;
}

int run_psf(const PsfArguments& args, const PsfOptionHandles& handles) {
  if (args.out.empty() && args.profile_csv.empty())
    throw ConfigError({"--out", 0, 0}, "out", "nothing to write: give --out FILE.exr, --profile-csv FILE.csv or both");
  // Both outputs are written beside and renamed into place; a link standing at either is refused
  // before anything is computed (core/atomic_file.h).
  if (!args.out.empty()) refuse_symbolic_link(args.out, "--out");
  if (!args.profile_csv.empty()) refuse_symbolic_link(args.profile_csv, "--profile-csv");
  const GlareModel model = parse_glare_model(args.model);
  if (model == GlareModel::luidolt) return run_luidolt_psf(args, handles);
  const bool analytic = model == GlareModel::spencer || model == GlareModel::cie;
  const bool human = model == GlareModel::human;
  const GlareModel far_model = model == GlareModel::hybrid ? parse_glare_model(args.far_field) : human ? GlareModel::cie : model;
  // The human eye is the eye model's (dynamic unless --mode says otherwise), spectral, as in sessions.
  const std::string mode = human && args.mode.empty() ? "dynamic" : args.mode;
  bool refraction_given = false;
  for (const CLI::Option* option : handles.refraction) refraction_given = refraction_given || option->count() > 0;
  std::vector<ModelOption> checks = {
      {handles.age, model != GlareModel::ritschel || refraction_given,
       "the analytic models (--model human, spencer, cie or hybrid) and the observer's refraction (--sphere-dioptres, "
       "--cylinder-dioptres, --spectacles, --viewing-distance-m, ...)"},
      {handles.regime, far_model == GlareModel::spencer, "Spencer's PSF (--model spencer, or hybrid with --far-field spencer)"},
      {handles.flare_lines, model == GlareModel::spencer, "Spencer's PSF (--model spencer)"},
      // --age-years also sets the refraction's accommodation amplitude, so it applies to every model.
      {handles.pigmentation, far_model == GlareModel::cie, "the CIE PSF (--model human or cie, or hybrid with --far-field cie)"},
      {handles.far_field, model == GlareModel::hybrid, "--model hybrid"},
      {handles.handover, model == GlareModel::hybrid || human, "--model hybrid and human"},
      {handles.dpp, model != GlareModel::ritschel, "the images of --model human, spencer, cie and hybrid"},
      {handles.field_luminance, !mode.empty(), "the eye model (--mode, or --model human)"},
      {handles.eye_from, !mode.empty(), "the eye model (--mode, or --model human)"}};
  for (const CLI::Option* option : handles.wave)
    if (option != handles.field_luminance && option != handles.eye_from) checks.push_back({option, !analytic, "the wave-optics eye (--model human, ritschel or hybrid)"});
  refuse_unused_options(checks, args.model);
  if (analytic) return write_analytic(model, args);
  PsfEye eye;
  ApertureGeometry geometry = psf_geometry(args, handles, mode, eye);
  const ObserverRefraction refraction = observer_refraction(args, handles, geometry);
  PsfOptions options;
  options.grid_px = args.grid_px;
  options.aperture_width_mm = args.aperture_width_mm;
  options.supersampling = args.supersampling;
  options.wavelength_nm = args.wavelength_nm;
  options.spectral = args.spectral || human;
  options.wavelength_samples = args.wavelength_samples;
  options.phase = parse_phase_form(args.fresnel);
  // With the refraction, a spectral PSF takes one FFT per wavelength with the eye's LCA even where the
  // residual is zero (glare/wave/chromatic_psf.h).
  options.observer_refraction = refraction.active;
  check_grid(geometry, options,
             mode.empty() || handles.pupil->count() > 0 ? "--pupil-diameter-mm" : "the eye model at --time-s");
  if (refraction.active) check_refraction_sampling(geometry, options, refraction.flags);
  const double reach_deg = wave_reach_deg(options);
  const std::optional<HybridHandover> handover =
      model == GlareModel::hybrid || human ? std::optional(hybrid_handover(args, options, reach_deg)) : std::nullopt;
  std::cout << refraction.summary;
  std::string backend_name;
  const Psf psf = wave_psf(args, handles.backend->count() > 0, refraction, geometry, options,
                           handover ? std::optional(args.degrees_per_pixel) : std::nullopt, backend_name);
  if (handover) return write_hybrid(args, psf, *handover, human, eye);
  if (!args.out.empty()) write_psf_exr(args.out, psf);
  if (!args.out.empty()) std::cout << "psf: wrote " << args.out << ": " << psf.size_px << "x" << psf.size_px << " px, "
            << (psf.channels == 1 ? "Y" : "R,G,B") << ", " << psf.degrees_per_pixel << " deg/px, pupil "
            << geometry.pupil_diameter_mm << " mm, fresnel " << args.fresnel << ", backend " << backend_name << "\n";
  write_profile(args.profile_csv, image_profile_per_sr(psf, PixelLayout::uniform_angle, profile_angles_deg(), reach_deg));
  return 0;
}

}  // namespace

Action add_psf_command(CLI::App& app) {
  auto args = std::make_shared<PsfArguments>();
  auto handles = std::make_shared<PsfOptionHandles>();
  CLI::App* command = app.add_subcommand("psf", "Compute the eye's point-spread function and write it as EXR");
  add_psf_options(command, *args, *handles);
  return [=]() { return report_errors([&]() { return run_psf(*args, *handles); }); };
}

}  // namespace glarelab::cli
