// The observer's refraction in a session's glare stage: a condition's residual (computed from the
// experiment file by runner/session/condition_refraction.h, checked against the closed form of
// Kakimoto's Eq. 13) blurs the glare PSF by the geometric disc of the residual (second moments), the
// correcting spectacles leave it sharp, no refraction leaves every frame bit-identical, and the CPU
// backend computes a PSF with a refraction as the chromatic PSF (one FFT per wavelength).
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <iostream>
#include <numbers>
#include <string>

#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/cpu/backend.h"
#include "glare/eye/eye_model.h"
#include "glare/wave/spectral_psf.h"
#include "protocols/experiment.h"
#include "runner/display/compute_context.h"
#include "runner/session/condition_refraction.h"
#include "stimuli/display_model.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A presbyope with 1 D of amplitude at a display 0.25 m away, without and with +3.25 D readers at
// 12 mm; glare static (the Ritschel eye) on a 512 grid.
const char* kPresbyope = R"(
[experiment]
name = "presbyope"
seed = 7
[display]
width_px = 256
height_px = 192
viewing_distance_mm = 250.0
pixel_pitch_mm = 0.2
peak_luminance_cd_m2 = 250.0
[scenes]
dot = { generator = "light_source", size_px = 64, disc_diameter_deg = 0.05, disc_fraction_of_peak = 0.9 }
[procedure]
type = "rating"
categories = ["sharpness"]
[observer.refraction]
sphere_dioptres = 0.0
accommodation_amplitude_dioptres = 1.0
[spectacles.readers]
sphere_dioptres = 3.25
[[conditions.rows]]
name = "naked"
scene = "dot"
[[conditions.rows]]
name = "readers"
scene = "dot"
spectacles = "readers"
[glare]
mode = "static"
backend = "cpu"
grid_px = 512
wavelength_samples = 16
)";

struct Moments {
  double xx = 0.0, yy = 0.0, xy = 0.0;  // second central moments, px^2
};

Moments channel_moments(const Psf& psf, int channel) {
  const int n = psf.size_px;
  double total = 0.0, mx = 0.0, my = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v = psf.at(channel, x, y);
      total += v, mx += v * x, my += v * y;
    }
  mx /= total, my /= total;
  Moments m;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double v = psf.at(channel, x, y) / total;
      m.xx += v * (x - mx) * (x - mx), m.yy += v * (y - my) * (y - my), m.xy += v * (x - mx) * (y - my);
    }
  return m;
}

TEST(RefractionSessionStage, ResidualIsKakimotosClosedFormAtTheDisplay) {
  const Experiment experiment = parse_experiment_text(kPresbyope, "presbyope.toml", "/");
  ASSERT_TRUE(models_observer_optics(experiment));
  const auto naked = condition_refraction(experiment, experiment.conditions[0]);
  const auto readers = condition_refraction(experiment, experiment.conditions[1]);
  ASSERT_TRUE(naked && readers);
  // Naked eye: V = -1 / 0.25 = -4 D, accommodation min(4, 1) = 1 D, E = V + 1 = -3 D (Eq. 13, 7).
  EXPECT_NEAR(naked->fixation.accommodation_dioptres, 1.0, 1e-12);
  EXPECT_NEAR(naked->fixation.residual.xx(), -3.0, 1e-12);
  EXPECT_NEAR(naked->fixation.residual.yy(), -3.0, 1e-12);
  EXPECT_NEAR(naked->fixation.residual.xy(), 0.0, 1e-12);
  EXPECT_EQ(naked->spectacles, "none");
  // Readers +3.25 D at 12 mm: at the lens -1 / 0.238 + 3.25 = -0.95168 D, at the cornea
  // -0.95168 / (1 + 0.012 x 0.95168) = -0.94094 D (Eq. 1): within the 1 D amplitude, E = 0.
  const double at_lens = -1.0 / 0.238 + 3.25;
  EXPECT_NEAR(readers->fixation.fixation_vergence.xx(), at_lens / (1.0 - 0.012 * at_lens), 1e-12);
  EXPECT_NEAR(readers->fixation.accommodation_dioptres, -at_lens / (1.0 - 0.012 * at_lens), 1e-12);
  EXPECT_NEAR(readers->fixation.residual.xx(), 0.0, 1e-12);
  EXPECT_EQ(readers->spectacles, "readers");
  const std::string text = describe_condition_refraction(*naked);
  EXPECT_NE(text.find("residual sphere -3 D, cylinder 0 D"), std::string::npos) << text;
}

// The second moment of |FT(A e^{i phi})|^2 is that of |FT(A)|^2 plus the pupil-weighted mean of
// |grad phi|^2 (the cross term vanishes for a real A): the glare PSF with a residual E has the
// moments of the PSF without it plus the geometric disc's, (E r_p)^2 / 4 per axis (rad^2). The
// eye's LCA makes E differ by wavelength, E(lambda) = E + Rx(575) - Rx(lambda) with Thibos' Rx =
// p - q / (lambda - c) (Applied Optics 31:3594, 1992; written out here), and a channel's PSF is the
// CMF-weighted mean of the wavelengths' PSFs, so the green channel's disc moment is
// (r_p^2 / 4) sum_i w_G,i E(lambda_i)^2 / sum_i w_G,i (the clamping of out-of-gamut negatives,
// about 1 % in green, left aside).
double green_mean_square_error(double e_dioptres, int wavelengths) {
  const auto rx = [](double nm) { return 1.68524 - 0.63346 / (nm / 1000.0 - 0.21410); };
  double weighted = 0.0, weights = 0.0;
  for (const SpectralSample& sample : spectral_samples(wavelengths)) {
    const double e = e_dioptres + rx(575.0) - rx(sample.wavelength_nm);
    weighted += sample.weight.g * e * e;
    weights += sample.weight.g;
  }
  return weighted / weights;
}

TEST(RefractionSessionStage, ThreeDioptreResidualBlursThePsfByTheGeometricDisc) {
  const Experiment experiment = parse_experiment_text(kPresbyope, "presbyope.toml", "/");
  const DioptricPower residual = condition_refraction(experiment, experiment.conditions[0])->fixation.residual;
  const DioptricPower corrected = condition_refraction(experiment, experiment.conditions[1])->fixation.residual;
  GlareStage stage(experiment.glare, experiment.display, experiment.seed);
  const double field_cd_m2 = 50.0;
  EyeState state;
  const Psf sharp = *stage.display_psf(GlareMode::static_eye, 0.0, field_cd_m2, &state);
  stage.set_refraction(residual);
  const Psf blurred = *stage.display_psf(GlareMode::static_eye, 0.0, field_cd_m2);
  stage.set_refraction(corrected);
  const Psf readers = *stage.display_psf(GlareMode::static_eye, 0.0, field_cd_m2);
  const double deg_per_px = DisplayModel(experiment.display).degrees_per_pixel_at_centre();
  const double disc_radius_deg = 3.0 * 0.5e-3 * state.pupil_diameter_mm * kDegPerRad;  // at 575 nm
  const double pupil_radius_deg = 0.5e-3 * state.pupil_diameter_mm * kDegPerRad;
  const double expected_px2 =
      green_mean_square_error(-3.0, 16) * pupil_radius_deg * pupil_radius_deg / 4.0 / (deg_per_px * deg_per_px);
  const Moments m0 = channel_moments(sharp, 1), m1 = channel_moments(blurred, 1), m2 = channel_moments(readers, 1);
  std::cout << "pupil " << state.pupil_diameter_mm << " mm, disc radius " << disc_radius_deg << " deg = "
            << disc_radius_deg / deg_per_px << " px; G moments px^2: sharp " << m0.xx << " " << m0.yy << ", -3 D "
            << m1.xx << " " << m1.yy << " " << m1.xy << " (geometric with LCA " << expected_px2 << ", at 575 nm alone "
            << disc_radius_deg * disc_radius_deg / 4.0 / (deg_per_px * deg_per_px) << "), readers " << m2.xx << " "
            << m2.yy << "\n";
  EXPECT_NEAR(m1.xx - m0.xx, expected_px2, 0.04 * expected_px2);
  EXPECT_NEAR(m1.yy - m0.yy, expected_px2, 0.04 * expected_px2);
  EXPECT_NEAR(m1.xy - m0.xy, 0.0, 0.01 * expected_px2);  // a sphere: a round disc
  // With the readers E = 0 at 575 nm: only the LCA is left, a few per cent of the uncorrected blur.
  EXPECT_LT(m2.xx - m0.xx, 0.05 * expected_px2);
  EXPECT_LT(m2.yy - m0.yy, 0.05 * expected_px2);
}

ImageRGBA dot_frame() {
  ImageRGBA frame(96, 64, 0.5f);
  for (int y = 30; y < 34; ++y)
    for (int x = 46; x < 50; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 2000.0f;
  return frame;
}

bool same_bits(const ImageRGBA& a, const ImageRGBA& b) {
  return a.width_px == b.width_px && a.height_px == b.height_px && a.rgba == b.rgba;
}

// No refraction: a stage that never heard of one and a stage that showed a condition with one and
// then one without give the same frames bit for bit, on the float64 backend and on auto's planned
// float32 path, static and dynamic; and those frames are not the refracted one.
TEST(RefractionSessionStage, NoRefractionIsBitIdentical) {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  for (const GlareBackendRequest backend : {GlareBackendRequest::cpu, GlareBackendRequest::automatic}) {
    GlareSpec spec;
    spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
    spec.backend = backend;
    spec.grid_px = 128;
    spec.wavelength_samples = 8;
    spec.skip_invisible = false;
    for (const GlareMode mode : {GlareMode::static_eye, GlareMode::dynamic}) {
      GlareStage plain(spec, display, 11), toggled(spec, display, 11);
      const ImageRGBA before = plain.apply(dot_frame(), mode, 0.25);
      toggled.set_refraction(DioptricPower::spherical(-0.5));
      const ImageRGBA refracted = toggled.apply(dot_frame(), mode, 0.25);
      toggled.set_refraction(std::nullopt);
      const ImageRGBA after = toggled.apply(dot_frame(), mode, 0.25);
      EXPECT_TRUE(same_bits(before, after)) << spelling(backend) << " " << to_string(mode);
      EXPECT_FALSE(same_bits(before, refracted)) << spelling(backend) << " " << to_string(mode);
    }
  }
}

// The hybrid eye's near field is the wave-optics PSF: it carries the refraction too, and without
// one the hybrid frame is the same bit for bit.
TEST(RefractionSessionStage, HybridNearFieldCarriesTheRefraction) {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  GlareSpec spec;
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.skip_invisible = false;
  spec.model = GlareModel::hybrid;
  GlareStage plain(spec, display, 3), toggled(spec, display, 3);
  const ImageRGBA before = plain.apply(dot_frame(), GlareMode::static_eye, 0.0);
  toggled.set_refraction(DioptricPower::spherical(-1.0));
  const ImageRGBA refracted = toggled.apply(dot_frame(), GlareMode::static_eye, 0.0);
  toggled.set_refraction(std::nullopt);
  const ImageRGBA after = toggled.apply(dot_frame(), GlareMode::static_eye, 0.0);
  EXPECT_TRUE(same_bits(before, after));
  // The dot's centre loses light to the blur: the 1 D disc through the static eye's pupil is
  // several display pixels wide, the 4 px dot's centre keeps less of its own light.
  EXPECT_LT(refracted.pixel(48, 32)[1], 0.9f * before.pixel(48, 32)[1]);
}

// [glare] backend "gl" computes a PSF with a refraction itself (GlPsf::chromatic: the refraction's
// phase and the eye's LCA, one FFT per wavelength), within 1e-5 of the float64 CPU one; so does
// "auto" (the planned float32 path here, glare/cpu/planned_chromatic_psf.h), and the glare_backend
// record says which computed them.
TEST(RefractionSessionStage, PsfWithARefractionOnEveryBackend) {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  const DioptricPower residual = DioptricPower::from_prescription({-0.5, -1.0, 120.0});
  spec.backend = GlareBackendRequest::cpu;
  GlareStage reference(spec, display, 5);
  reference.set_refraction(residual);
  const Psf expected = *reference.display_psf(GlareMode::static_eye, 0.0, 20.0);
  const double peak = *std::max_element(expected.values.begin(), expected.values.end());

  spec.backend = GlareBackendRequest::gl;
  GlareStage gl(spec, display, 5, gl::compute_context_factory());
  gl.set_refraction(residual);
  const Psf on_gl = *gl.display_psf(GlareMode::static_eye, 0.0, 20.0);
  ASSERT_EQ(on_gl.values.size(), expected.values.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < expected.values.size(); ++i)
    largest = std::max(largest, std::abs(on_gl.values[i] - expected.values[i]));
  std::printf("gl against cpu float64, display PSF with a refraction: max |difference| / peak %.3g\n", largest / peak);
  EXPECT_LT(largest, 1e-5 * peak);
  EXPECT_NE(gl.refraction_backend_reason().find("refraction: gl,"), std::string::npos) << gl.refraction_backend_reason();
  EXPECT_EQ(gl.refraction_backend_reason().find("does not carry"), std::string::npos);

  spec.backend = GlareBackendRequest::automatic;
  GlareStage planned(spec, display, 5, gl::compute_context_factory());
  planned.set_refraction(residual);
  const Psf on_planned = *planned.display_psf(GlareMode::static_eye, 0.0, 20.0);
  ASSERT_EQ(on_planned.values.size(), expected.values.size());
  double planned_largest = 0.0;
  for (std::size_t i = 0; i < expected.values.size(); ++i)
    planned_largest = std::max(planned_largest, std::abs(on_planned.values[i] - expected.values[i]));
  EXPECT_LT(planned_largest, 1e-5 * peak);
  EXPECT_NE(planned.refraction_backend_reason().find("refraction: cpu float32 planned,"), std::string::npos)
      << planned.refraction_backend_reason();
  EXPECT_NE(reference.refraction_backend_reason().find("refraction: cpu float64,"), std::string::npos);
}

// The CPU backend with a refraction: the spectral PSF is compute_chromatic_psf's, bit for bit; a
// geometry without one keeps the scaled reference (spectral_psf_from_reference).
TEST(RefractionSessionStage, CpuBackendComputesTheChromaticPsfWithARefraction) {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  geometry.refraction_error = DioptricPower::from_prescription({-1.0, -1.0, 30.0});
  PsfOptions options;
  options.grid_px = 128;
  options.spectral = true;
  options.wavelength_samples = 8;
  CpuGlareBackend backend;
  const Psf with_refraction = backend.psf(geometry, options);
  ChromaticPsfOptions chromatic;
  chromatic.raster.grid_px = 128;
  chromatic.raster.aperture_width_mm = options.aperture_width_mm;
  chromatic.raster.supersampling = options.supersampling;
  chromatic.wavelength_samples = 8;
  EXPECT_EQ(with_refraction.values, compute_chromatic_psf(geometry, chromatic).spectral.psf.values);

  geometry.refraction_error = DioptricPower{};
  const Psf without = backend.psf(geometry, options);
  PsfOptions mono = options;
  mono.spectral = false;
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = 8;
  spectral.reference_wavelength_nm = options.wavelength_nm;
  EXPECT_EQ(without.values, spectral_psf_from_reference(backend.psf(geometry, mono), spectral).psf.values);
  // A stated refraction with a zero residual still takes the per-wavelength FFTs (the eye's LCA).
  options.observer_refraction = true;
  EXPECT_EQ(backend.psf(geometry, options).values, compute_chromatic_psf(geometry, chromatic).spectral.psf.values);
}

}  // namespace
}  // namespace glarelab
