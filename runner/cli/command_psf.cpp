#include <iostream>
#include <memory>

#include "glare/fibre_gratings.h"
#include "glare/psf_cpu.h"
#include "glare/psf_exr.h"
#include "glare/spectral_psf.h"
#include "runner/cli/commands.h"

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
  std::string out;
};

}  // namespace

Action add_psf_command(CLI::App& app) {
  auto args = std::make_shared<PsfArguments>();
  CLI::App* command = app.add_subcommand("psf", "Compute the eye's point-spread function and write it as EXR");
  command->add_option("--pupil-diameter-mm", args->pupil_diameter_mm, "Pupil diameter (mm)")->check(CLI::Range(0.5, 12.0))->capture_default_str();
  command->add_option("--wavelength-nm", args->wavelength_nm,
                                     "One wavelength (nm): a one-channel Y PSF; with --spectral, the reference wavelength")
                         ->check(CLI::Range(300.0, 900.0))->capture_default_str();
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
      ->check(CLI::PositiveNumber)->capture_default_str();
  command->add_option("--supersampling", args->supersampling, "Sub-samples per pixel side (>= 2)")->check(CLI::Range(2, 16))->capture_default_str();
  command->add_option("--fresnel", args->fresnel, "Phase before the FFT: none (Fraunhofer), defocus, paper (Eq. 3, d = 24 mm)")
      ->check(CLI::IsMember({"none", "defocus", "paper"}))->capture_default_str();
  command->add_option("--defocus-dioptres", args->defocus_dioptres, "Accommodation error (dioptres) for --fresnel defocus")->capture_default_str();
  command->add_option("--backend", args->backend, "Compute backend")->check(CLI::IsMember({"cpu"}))->capture_default_str();
  command->add_flag("--gratings", args->gratings, "Add radial lens-fibre gratings (annulus 1.5-2.5 mm, halo at 3 deg for 568 nm)");
  command->add_option("--out", args->out, "Output EXR file")->required();
  return [=]() {
    return report_errors([&]() {
      ApertureGeometry geometry;
      geometry.pupil_diameter_mm = args->pupil_diameter_mm;
      geometry.defocus_dioptres = args->defocus_dioptres;
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
      MonochromaticPsfOptions options;
      options.raster.grid_px = args->grid_px;
      options.raster.aperture_width_mm = args->aperture_width_mm;
      options.raster.supersampling = args->supersampling;
      options.wavelength_nm = args->wavelength_nm;
      options.phase = parse_phase_form(args->fresnel);
      const MonochromaticPsfResult mono = compute_monochromatic_psf(geometry, options);
      if (!mono.sampling_warning.empty()) std::cerr << "warning: " << mono.sampling_warning << "\n";
      Psf psf = mono.psf;
      if (args->spectral) {
        SpectralPsfOptions spectral;
        spectral.wavelength_samples = args->wavelength_samples;
        spectral.reference_wavelength_nm = args->wavelength_nm;
        const SpectralPsfResult result = spectral_psf_from_reference(mono.psf, spectral);
        std::cout << "psf: clamped negative Rec.709 fraction R " << result.clamped_negative_fraction[0] << ", G "
                  << result.clamped_negative_fraction[1] << ", B " << result.clamped_negative_fraction[2] << "\n";
        psf = result.psf;
      }
      write_psf_exr(args->out, psf);
      std::cout << "psf: wrote " << args->out << ": " << psf.size_px << "x" << psf.size_px << " px, "
                << (psf.channels == 1 ? "Y" : "R,G,B") << ", " << psf.degrees_per_pixel << " deg/px, pupil "
                << args->pupil_diameter_mm << " mm, fresnel " << args->fresnel << ", backend cpu\n";
      return 0;
    });
  };
}

}  // namespace glarelab::cli
