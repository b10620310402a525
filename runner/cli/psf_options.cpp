#include "runner/cli/psf_options.h"

#include <stdexcept>

#include "glare/eye/aperture_components.h"
#include "runner/cli/option_checks.h"

namespace glarelab::cli {
namespace {

void add_wave_options(CLI::App* command, PsfArguments& args, PsfOptionHandles& handles) {
  command->add_option("--pupil-diameter-mm", args.pupil_diameter_mm, "Pupil diameter (mm)")->check(finite_number_in(0.5, 12.0, "mm"))->capture_default_str();
  command->add_option("--wavelength-nm", args.wavelength_nm,
                                     "One wavelength (nm): a one-channel Y PSF; with --spectral, the reference wavelength")
                         ->check(finite_number_in(300.0, 900.0, "nm"))->capture_default_str();
  command->add_flag("--spectral", args.spectral, "Spectral PSF in linear Rec.709 R,G,B (chromatic blur, CIE 1931 weights)");
  command->add_option("--wavelength-samples", args.wavelength_samples, "Wavelength samples over 380-770 nm for --spectral")
      ->check(CLI::Range(1, 1024))->capture_default_str();
  command->add_option("--grid", args.grid_px,
                      "Aperture and PSF grid size N (even); for human, spencer, cie and hybrid also the side of the image "
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
  command->add_option("--aperture-width-mm", args.aperture_width_mm, "Side of the square aperture grid (mm)")
      ->check(finite_positive_number("mm"))->capture_default_str();
  command->add_option("--supersampling", args.supersampling, "Sub-samples per pixel side (>= 2)")->check(CLI::Range(2, 16))->capture_default_str();
  command->add_option("--fresnel", args.fresnel, "Phase before the FFT: none (Fraunhofer), defocus, paper (Eq. 3, d = 24 mm)")
      ->check(CLI::IsMember({"none", "defocus", "paper"}))->capture_default_str();
  handles.pupil = command->get_option("--pupil-diameter-mm");
  handles.defocus =
      command->add_option("--defocus-dioptres", args.defocus_dioptres,
                          "Accommodation error (dioptres) for --fresnel defocus (with --mode: replaces the eye's)")
          ->check(finite_number())
          ->capture_default_str();
  handles.backend = add_choice_option(command, "--backend", args.backend,
                                      "Compute backend: cpu (FFTW double), gl, or auto (gl on a hardware GPU)");
  CLI::Option* gratings_option = command->add_flag(
      "--gratings", args.gratings, "Add radial lens-fibre gratings (annulus 1.5-2.5 mm, halo at 3 deg for 568 nm)");
  CLI::Option* mode_option =
      command->add_option("--mode", args.mode,
                          "Aperture from the eye model (docs/EYE_MODEL.md) in this condition: dynamic, static (frozen "
                          "at the eye's static time), control (no glare: a delta PSF)")
          ->check(CLI::IsMember({"dynamic", "static", "control"}))
          ->excludes(gratings_option);
  handles.field_luminance =
      command->add_option("--field-luminance-cd-m2", args.field_luminance_cd_m2,
                          "Field luminance the eye model adapts to (cd/m2; its pupil, Eq. 1-2): with --mode, and for "
                          "the human eye")
          ->check(finite_number_in(1e-4, 1e9, "cd/m2"))
          ->capture_default_str();
  handles.eye_from = command->add_option("--eye-from", args.eye_from,
                                         "Experiment file whose [glare.eye] table sets the eye model (docs/EXPERIMENT_FILES.md): "
                                         "with --mode, and for the human eye and --model luidolt");
  command->add_option("--time-s", args.time_s, "Time of the eye model (s), at most 86400 (24 h)")
      ->check(eye_model_time_s())
      ->needs(mode_option)
      ->capture_default_str();
  command->add_option("--seed", args.seed, "Seed of the eye model")->check(seed_check())->needs(mode_option)->capture_default_str();
  command->add_option("--components", args.components,
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
}

void add_model_options(CLI::App* command, PsfArguments& args, PsfOptionHandles& handles) {
  command->add_option("--model", args.model,
                          "Glare model: human (the default eye of sessions: the eye model's spectral PSF in --mode, "
                          "dynamic unless given, at the light CIE 146:2002 gives the observer on every ring around the "
                          "source, CIE beyond), ritschel (the wave-optics eye above), spencer (Spencer et al. 1995), "
                          "cie (CIE 146:2002), hybrid (the wave-optics eye near the source, an analytic far field "
                          "beyond, joined by one energy rule), luidolt (Luidolt 2020's glare kernel: static particles, "
                          "the Fresnel term of Eq. 5.6)")
          ->check(CLI::IsMember({"human", "ritschel", "spencer", "cie", "hybrid", "luidolt"}))
          ->capture_default_str();
  handles.regime =
      command->add_option("--regime", args.regime, "Spencer's mixture: photopic (Eq. 5), mesopic (Eq. 8), scotopic (Eq. 9)")
          ->check(CLI::IsMember({"photopic", "mesopic", "scotopic"}))
          ->capture_default_str();
  handles.flare_lines =
      command->add_flag("--flare-lines", args.flare_lines,
                        "Spencer's flare lines (section 3.2): random radial lines multiplied into the corona (f1, f2) "
                        "and the halo (f3), each ring keeping its energy, so --profile-csv is unchanged");
  command->add_option("--flare-seed", args.flare_seed, "Seed of the flare lines (a session uses its own seed)")
      ->check(seed_check())
      ->needs(handles.flare_lines)
      ->capture_default_str();
  handles.age =
      command->add_option("--age-years", args.age_years, "Observer's age (years): Spencer Eq. 10, CIE 146, and with a refraction flag the accommodation "
                          "amplitude (Hofstetter 1950: 18.5 - 0.3 age D)")
          ->check(finite_number_in(1.0, 100.0, "years"))
          ->capture_default_str();
  handles.pigmentation =
      command->add_option("--pigmentation", args.pigmentation,
                          "CIE 146 eye pigmentation: 0 very dark eyes, 0.5 brown, 1 blue-green")
          ->check(finite_number_in(0.0, 1.0, ""))
          ->capture_default_str();
  handles.far_field =
      command->add_option("--far-field", args.far_field, "The hybrid's analytic far field: spencer or cie")
          ->check(CLI::IsMember({"spencer", "cie"}))
          ->capture_default_str();
  handles.handover =
      command->add_option("--handover-deg", args.handover_deg,
                          "The hybrid's and the human eye's hand-over annulus INNER,OUTER (degrees from the source; default: from half of 0.9 "
                          "to 0.9 of the wave PSF's reach, which the outer angle must not pass)")
          ->delimiter(',')
          ->expected(2)
          ->check(finite_positive_number("deg"));
  handles.dpp =
      command->add_option("--degrees-per-pixel", args.degrees_per_pixel,
                          "Angle of the image's centre pixel for human, spencer, cie and hybrid (a flat display whose pixel "
                          "subtends it at the line of sight)")
          ->check(finite_number_in(1e-4, 2.0, "deg"))
          ->capture_default_str();
  command->add_option("--profile-csv", args.profile_csv,
                      "Also write the radial profile (angle_deg,psf_per_sr) at log-spaced angles from 0.01 to 90 deg, "
                      "20 or more per decade. spencer: the whole P of Eq. 5/8/9 with the halo at 568 nm; cie: the CIE "
                      "formula (the scattered light); human, ritschel, hybrid: the azimuthal mean of the image's pixel "
                      "densities (value / solid angle; R,G,B by Rec.709 luminance weights) on 1-pixel rings, at the "
                      "angles the image reaches")
      ->check(file_extension_in({".csv"}, "the profile file"));
  // EXR only: the PSF is linear data summing to 1, which an 8-bit PNG would round to nothing.
  command->add_option("--out", args.out,
                      "Output EXR file (unit sum per channel; for human, spencer, cie and hybrid the sum counts only the "
                      "light within the image). --out, --profile-csv or both.")
      ->check(file_extension_in({".exr"}, "the PSF file"));
}

// The observer's refraction (glare/refraction/eye_refraction.h, docs/REFRACTION.md).
void add_refraction_options(CLI::App* command, PsfArguments& args, PsfOptionHandles& handles) {
  CLI::Option* sphere =
      command->add_option("--sphere-dioptres", args.refraction.sphere_dioptres,
                          "The eye's refractive error as its correcting prescription: sphere (dioptres, at "
                          "--vertex-distance-mm)")
          ->check(finite_number_in(-kMaxSphereDioptres, kMaxSphereDioptres, "D"));
  CLI::Option* cylinder =
      command->add_option("--cylinder-dioptres", args.refraction.cylinder_dioptres,
                          "The correcting prescription's cylinder (dioptres; minus-cylinder form, a plus cylinder is "
                          "transposed and said so)")
          ->check(finite_number_in(-kMaxCylinderDioptres, kMaxCylinderDioptres, "D"));
  CLI::Option* axis =
      command->add_option("--axis-deg", args.refraction.axis_deg, "The correcting prescription's cylinder axis (TABO degrees, 0-180)")
          ->check(finite_number_in(0.0, kMaxAxisDeg, "deg"))
          ->needs(cylinder);
  CLI::Option* spectacles =
      command->add_option("--spectacles", args.refraction.spectacles,
                          "Spectacle lenses worn, SPHERE,CYLINDER,AXIS (dioptres, dioptres, TABO degrees) at "
                          "--vertex-distance-mm")
          ->check(sphero_cylinder_check());
  CLI::Option* viewing =
      command->add_option("--viewing-distance-m", args.refraction.viewing_distance_m,
                          "Distance of the fixated point source from the cornea (m; default: infinity)")
          ->check(finite_positive_number("m"));
  CLI::Option* amplitude =
      command->add_option("--accommodation-amplitude-dioptres", args.refraction.accommodation_amplitude_dioptres,
                          "Amplitude of accommodation (dioptres; default: Table 2's 11.93, or from --age-years by "
                          "Hofstetter 1950)")
          ->check(finite_number_in(0.0, 20.0, "D"))
          ->excludes(handles.age);
  CLI::Option* vertex =
      command->add_option("--vertex-distance-mm", args.refraction.vertex_distance_mm,
                          "Vertex distance of the prescription and of --spectacles (mm)")
          ->check(finite_number_in(0.0, 40.0, "mm"))
          ->capture_default_str();
  handles.cylinder = cylinder;
  handles.axis = axis;
  handles.amplitude = amplitude;
  handles.refraction = {sphere, cylinder, axis, spectacles, viewing, amplitude, vertex};
  for (const char* name : {"--pupil-diameter-mm", "--wavelength-nm", "--spectral", "--wavelength-samples",
                           "--aperture-width-mm", "--supersampling", "--fresnel", "--defocus-dioptres", "--backend",
                           "--gratings", "--mode", "--field-luminance-cd-m2", "--eye-from", "--time-s", "--seed", "--components"})
    handles.wave.push_back(command->get_option(name));
  for (const CLI::Option* option : handles.refraction) handles.wave.push_back(option);
}

}  // namespace

void add_psf_options(CLI::App* command, PsfArguments& args, PsfOptionHandles& handles) {
  add_wave_options(command, args, handles);
  add_model_options(command, args, handles);
  add_refraction_options(command, args, handles);
}

}  // namespace glarelab::cli
