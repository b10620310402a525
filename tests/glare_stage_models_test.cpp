// The glare stage with the analytic models (Spencer, CIE), the hybrid eye, the excess source and
// the gain (stimuli/glare_stage.h), each against a computation made here from the glare layer's
// parts: the analytic kernel convolved in float64 (energy per pixel in, luminance out), the clipped frame plus the excess's glare, and
// frame + gain (glared - frame).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "energy_convolution_reference.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/analytic/hybrid_psf.h"
#include "glare/cpu/psf.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

constexpr int kWidth = 96, kHeight = 64;

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = kWidth;
  display.height_px = kHeight;
  display.peak_luminance_cd_m2 = 200.0;
  return display;
}

GlareSpec spec_for(GlareModel model) {
  GlareSpec spec;
  spec.model = model;
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.spencer_regime = SpencerRegime::mesopic;
  spec.observer_eye = ObserverEye{45.0, 0.7};
  return spec;
}

ImageRGBA lamp_frame(float surround_cd_m2, float lamp_cd_m2) {
  ImageRGBA frame(kWidth, kHeight, surround_cd_m2);
  for (int y = 28; y < 32; ++y)
    for (int x = 44; x < 48; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp_cd_m2;
  return frame;
}

DisplayKernel kernel_for(const AnalyticPsf& psf) {
  const DisplaySpec display = small_display();
  return analytic_display_kernel(psf, DisplayGeometry{display.viewing_distance_mm, display.pixel_pitch_mm}, kWidth - 1,
                                 kHeight - 1, 2);
}

double max_abs_difference(const ImageRGBA& a, const ImageRGBA& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, std::abs(static_cast<double>(a.rgba[i]) - b.rgba[i]));
  return worst;
}

TEST(GlareStageModels, SpencerAndCieFramesAreTheKernelConvolution) {
  const ImageRGBA frame = lamp_frame(1.0f, 5000.0f);
  for (GlareModel model : {GlareModel::spencer, GlareModel::cie}) {
    GlareStage stage(spec_for(model), small_display(), 1);
    GlareFrameReport report;
    const ImageRGBA glared = stage.apply(frame, GlareMode::static_eye, 0.0, &report);
    EXPECT_TRUE(report.convolved);
    EXPECT_EQ(report.model, model);
    const AnalyticPsf psf = model == GlareModel::cie ? AnalyticPsf::cie(ObserverEye{45.0, 0.7})
                                                     : AnalyticPsf::spencer(SpencerRegime::mesopic, 0.0, ObserverEye{45.0, 0.7});
    const ImageRGBA expected = test::convolve_as_energy_float64(frame, kernel_for(psf), small_display());
    EXPECT_LT(max_abs_difference(glared, expected), 1e-6 * 5000.0) << to_string(model);
    // Glare is visible: the surround next to the lamp is brighter than it was.
    EXPECT_GT(glared.pixel(40, 30)[1], 1.01f);
  }
}

TEST(GlareStageModels, ExcessSourceLeavesAFrameBelowThePeakUnchangedBitForBit) {
  GlareSpec spec = spec_for(GlareModel::spencer);
  spec.source = GlareSource::excess;
  GlareStage stage(spec, small_display(), 1);
  const ImageRGBA below = lamp_frame(3.0f, 199.9f);  // peak 200
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(below, GlareMode::dynamic, 0.0, &report);
  EXPECT_FALSE(report.convolved);
  ASSERT_EQ(out.rgba.size(), below.rgba.size());
  EXPECT_EQ(0, std::memcmp(out.rgba.data(), below.rgba.data(), below.rgba.size() * sizeof(float)));
}

TEST(GlareStageModels, ExcessSourceSpreadsOnlyWhatTheDisplayCannotShow) {
  GlareSpec spec = spec_for(GlareModel::cie);
  spec.source = GlareSource::excess;
  GlareStage stage(spec, small_display(), 1);
  const ImageRGBA frame = lamp_frame(3.0f, 2200.0f);
  const ImageRGBA out = stage.apply(frame, GlareMode::static_eye, 0.0);
  // Expected: min(frame, 200) + excess convolved, the excess being 2000 on the lamp.
  ImageRGBA excess = frame, clipped = frame;
  for (std::size_t i = 0; i < frame.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      excess.rgba[i + c] = std::max(frame.rgba[i + c] - 200.0f, 0.0f);
      clipped.rgba[i + c] = std::min(frame.rgba[i + c], 200.0f);
    }
  const ImageRGBA spread =
      test::convolve_as_energy_float64(excess, kernel_for(AnalyticPsf::cie(ObserverEye{45.0, 0.7})), small_display());
  double worst = 0.0;
  for (std::size_t i = 0; i < frame.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(static_cast<double>(out.rgba[i + c]) - (clipped.rgba[i + c] + spread.rgba[i + c])));
  EXPECT_LT(worst, 1e-5 * 2000.0);
  // The surround gains exactly the excess's glare, not the glare of the 3 cd/m2 surround itself.
  EXPECT_NEAR(out.pixel(10, 10)[0], 3.0 + spread.pixel(10, 10)[0], 1e-4);
}

TEST(GlareStageModels, GainScalesTheChangeGlareMakes) {
  const ImageRGBA frame = lamp_frame(0.5f, 3000.0f);
  GlareStage stage(spec_for(GlareModel::spencer), small_display(), 1);
  const ImageRGBA full = stage.apply(frame, GlareMode::static_eye, 0.0);
  for (double gain : {0.0, 0.25, 4.0}) {
    stage.set_condition(GlareModel::spencer, gain);
    GlareFrameReport report;
    const ImageRGBA scaled = stage.apply(frame, GlareMode::static_eye, 0.0, &report);
    EXPECT_EQ(report.gain, gain);
    for (std::size_t i = 0; i < frame.rgba.size(); i += 4)
      for (int c = 0; c < 3; ++c) {
        const double expected = std::max(0.0, frame.rgba[i + c] + gain * (static_cast<double>(full.rgba[i + c]) - frame.rgba[i + c]));
        ASSERT_NEAR(scaled.rgba[i + c], expected, 1e-6 * 3000.0 * std::max(1.0, gain)) << "gain " << gain;
      }
  }
}

TEST(GlareStageModels, HybridIsTheNearWaveOpticsPartPlusTheFarAnalyticPart) {
  GlareSpec spec = spec_for(GlareModel::hybrid);
  spec.hybrid_far_field = GlareModel::cie;
  GlareStage stage(spec, small_display(), 1);
  const ImageRGBA frame = lamp_frame(0.2f, 4000.0f);
  GlareFrameReport report;
  const ImageRGBA hybrid = stage.apply(frame, GlareMode::static_eye, 0.0, &report);
  ASSERT_TRUE(report.convolved);
  // The parts made here: the static eye's wave-optics PSF on the display, the hand-over, the CIE
  // kernel split into near and far.
  GlareStage ritschel(spec_for(GlareModel::ritschel), small_display(), 1);
  const std::optional<Psf> wave = ritschel.display_psf(GlareMode::static_eye, 0.0, mean_luminance(frame));
  ASSERT_TRUE(wave);
  const DisplaySpec display = small_display();
  const DisplayGeometry geometry{display.viewing_distance_mm, display.pixel_pitch_mm};
  const double reach = wave_psf_reach_deg(128, psf_degrees_per_pixel(kReferenceWavelengthNm, 10.0));
  const HandoverPixels handover = handover_pixels(default_handover(reach), geometry);
  const DisplayKernel analytic = kernel_for(AnalyticPsf::cie(ObserverEye{45.0, 0.7}));
  const Psf near = hybrid_near_psf(*wave, analytic_energy_inside(analytic, handover), handover);
  const DisplayKernel whole = test::far_plus_near_kernel(hybrid_far_kernel(analytic, handover), near);
  const ImageRGBA expected = test::convolve_as_energy_float64(frame, whole, small_display());
  EXPECT_LT(max_abs_difference(hybrid, expected), 2e-6 * 4000.0);
}

}  // namespace
}  // namespace glarelab
