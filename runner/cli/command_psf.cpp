#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <sstream>

#include "glare/aperture_components.h"
#include "glare/eye_model.h"
#include "glare/fibre_gratings.h"
#include "glare/glare_backend.h"
#include "glare/psf_cpu.h"
#include "glare/psf_exr.h"
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
  std::string out;
};

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
  command->add_option("--grid", args->grid_px, "Aperture and PSF grid size N (even)")
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
  // EXR only: the PSF is linear data summing to 1, which an 8-bit PNG would round to nothing.
  command->add_option("--out", args->out, "Output EXR file")->required()->check(file_extension_in({".exr"}, "the PSF file"));
  return [=]() {
    return report_errors([&]() {
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
      GlareBackendChoice choice = create_glare_backend(args->backend, {.gl_context = gl::compute_context_factory()});
      std::cout << "psf: " << choice.reason << "\n";
      Psf psf;
      if (!geometry.glare_enabled) {
        psf = delta_psf(options);
        std::cout << "psf: control condition: no glare, a delta PSF (the image passes through unchanged)\n";
      } else {
        try {
          psf = choice.backend->psf(geometry, options);
        } catch (const ClosedApertureError& error) {
          // A closed eye (a blink at --time-s, or only lids kept) lets no light through: no PSF exists.
          throw ConfigError({"psf", 0, 0}, args->mode.empty() ? "--pupil-diameter-mm" : "--time-s",
                            std::string("no light passes the aperture, so there is no PSF (") + error.what() + ")");
        }
        if (!choice.backend->last_warning().empty()) std::cerr << "warning: " << choice.backend->last_warning() << "\n";
      }
      write_psf_exr(args->out, psf);
      std::cout << "psf: wrote " << args->out << ": " << psf.size_px << "x" << psf.size_px << " px, "
                << (psf.channels == 1 ? "Y" : "R,G,B") << ", " << psf.degrees_per_pixel << " deg/px, pupil "
                << geometry.pupil_diameter_mm << " mm, fresnel " << args->fresnel << ", backend " << choice.backend->name() << "\n";
      return 0;
    });
  };
}

}  // namespace glarelab::cli
