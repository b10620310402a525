// The CPU frame engine's PSFs with the observer's refraction in float32: the planned path of
// [glare] backend "auto" on a CPU (glare/cpu/float_glare.h) computes them itself, one float32 FFT per
// wavelength with the eye's LCA (glare/cpu/planned_chromatic_psf.h), against the float64 reference
// that `backend = "cpu"` names (glare/wave/chromatic_psf.h): the session's display PSF within 1e-5 of
// the reference's peak, and a session's frame with a refraction rendered through the frame engine
// (stimuli/frame_engine.h) within 1e-5 of the reference frame's peak, for the Ritschel eye and the
// human eye (whose near field is the wave-optics PSF). Each check also shows the refraction changed
// the result by far more than the tolerance, so a path that dropped it would fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "glare/refraction/dioptric_power.h"
#include "stimuli/frame_engine.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  return display;
}

GlareSpec small_glare(GlareBackendRequest backend, GlareModel model) {
  GlareSpec spec;
  spec.backend = backend;
  spec.model = model;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.skip_invisible = false;
  return spec;
}

// A 4 px dot of 1000 cd/m2 on 1 cd/m2, off the centre so that the glare is not symmetric.
ImageRGBA dot_frame() {
  const DisplaySpec display = small_display();
  ImageRGBA frame(display.width_px, display.height_px);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      const bool dot = std::abs(x - 40) < 2 && std::abs(y - 30) < 2;
      float* pixel = frame.pixel(x, y);
      for (int c = 0; c < 3; ++c) pixel[c] = dot ? 1000.0f : 1.0f;
      pixel[3] = 1.0f;
    }
  return frame;
}

// max |a - b| over every value of b, over b's largest value.
template <typename Values>
double max_over_peak(const Values& a, const Values& b, std::size_t stride = 1) {
  double largest = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (stride == 4 && i % 4 == 3) continue;  // alpha
    largest = std::max(largest, std::abs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
    peak = std::max(peak, std::abs(static_cast<double>(b[i])));
  }
  return largest / peak;
}

const DioptricPower kResidual = DioptricPower::from_prescription({-0.5, -1.0, 120.0});

TEST(RefractionFloatEngine, SessionPsfWithARefractionIsTheFloat32PathWithinTheReference) {
  const DisplaySpec display = small_display();
  GlareStage reference(small_glare(GlareBackendRequest::cpu, GlareModel::ritschel), display, 5);
  GlareStage planned(small_glare(GlareBackendRequest::automatic, GlareModel::ritschel), display, 5);
  ASSERT_EQ(planned.backend().kind(), GlareBackendKind::cpu_float32_planned) << planned.backend_reason();
  const Psf plain = *planned.display_psf(GlareMode::static_eye, 0.0, 20.0);
  reference.set_refraction(kResidual);
  planned.set_refraction(kResidual);
  for (const GlareMode mode : {GlareMode::static_eye, GlareMode::dynamic}) {
    const Psf expected = *reference.display_psf(mode, 0.5, 20.0);
    const Psf computed = *planned.display_psf(mode, 0.5, 20.0);
    ASSERT_EQ(computed.values.size(), expected.values.size());
    const double error = max_over_peak(computed.values, expected.values);
    std::printf("display PSF with a refraction (%s): float32 planned against float64, max |difference| / peak %.3g\n",
                mode == GlareMode::dynamic ? "dynamic" : "static", error);
    EXPECT_LT(error, 1e-5);
    // Computed in float32, not handed over from the reference.
    EXPECT_NE(computed.values, expected.values);
  }
  // The refraction blurs the PSF by far more than the tolerance.
  EXPECT_GT(max_over_peak(plain.values, reference.display_psf(GlareMode::static_eye, 0.0, 20.0)->values), 1e-2);
  EXPECT_NE(planned.refraction_backend_reason().find("cpu float32 planned, one FFT per wavelength (8)"),
            std::string::npos)
      << planned.refraction_backend_reason();
}

TEST(RefractionFloatEngine, SessionFrameWithARefractionThroughTheCpuEngine) {
  const DisplaySpec display = small_display();
  const ImageRGBA frame = dot_frame();
  for (const GlareModel model : {GlareModel::ritschel, GlareModel::human}) {
    const auto glared = [&](GlareBackendRequest backend, bool refraction) {
      FrameEngine engine(small_glare(backend, model), AdaptationTimeConstants{}, display, 3, {});
      if (refraction) engine.glare().set_refraction(kResidual);
      EyeFrameRequest request(frame);
      request.mode = GlareMode::static_eye;
      request.glared = true;
      request.time_s = 1.0;
      request.field_cd_m2 = 20.0;
      EXPECT_EQ(engine.kind(), FrameEngineKind::cpu);
      return engine.frame(request).image_cd_m2;
    };
    const ImageRGBA expected = glared(GlareBackendRequest::cpu, true);
    const ImageRGBA computed = glared(GlareBackendRequest::automatic, true);
    const ImageRGBA without = glared(GlareBackendRequest::automatic, false);
    const double error = max_over_peak(computed.rgba, expected.rgba, 4);
    std::printf("frame with a refraction (%s): cpu engine (float32 planned) against float64, max |difference| / "
                "peak %.3g\n",
                to_string(model).c_str(), error);
    EXPECT_LT(error, 1e-5) << to_string(model);
    EXPECT_GT(max_over_peak(without.rgba, expected.rgba, 4), 1e-3) << to_string(model);
  }
}

}  // namespace
}  // namespace glarelab
