// The frame engine seam (stimuli/frame_engine.h): which engine a compute backend brings, and the
// GL engine's frames against the CPU engine's (the float64 glare reference and the CPU perception
// stages) with every stage on, frame after frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "core/errors.h"
#include "core/gl/gl_context.h"
#include "runner/display/compute_context.h"
#include "stimuli/frame_engine.h"

namespace glarelab {
namespace {

constexpr int kWidthPx = 160;
constexpr int kHeightPx = 120;
constexpr double kPeriodS = 1.0 / 60.0;

GlareSpec glare_spec(GlareBackendRequest backend) {
  GlareSpec spec;
  spec.grid_px = 256;
  spec.wavelength_samples = 16;
  spec.skip_invisible = false;
  spec.backend = backend;
  return spec;
}

DisplaySpec display_spec() {
  DisplaySpec display;
  display.width_px = kWidthPx;
  display.height_px = kHeightPx;
  return display;
}

// A night street: a dim field, a grey wall and a small lamp far above the display's peak.
ImageRGBA night_scene() {
  ImageRGBA frame(kWidthPx, kHeightPx);
  for (int y = 0; y < kHeightPx; ++y)
    for (int x = 0; x < kWidthPx; ++x) {
      float* p = frame.pixel(x, y);
      const float wall = (x > 100 && y > 60) ? 12.0f : 0.4f;
      p[0] = wall;
      p[1] = 0.9f * wall;
      p[2] = 0.7f * wall;
      p[3] = 1.0f;
    }
  for (int y = 40; y < 43; ++y)
    for (int x = 50; x < 53; ++x) {
      float* p = frame.pixel(x, y);
      p[0] = p[1] = p[2] = 5000.0f;
    }
  return frame;
}

// Frame k of a static-glare interval on `scene`, every stage of `stages`.
EyeFrameRequest request_at(const ImageRGBA& scene, const PerceptionSettings& stages, int k) {
  EyeFrameRequest request(scene);
  request.mode = GlareMode::static_eye;
  request.glared = true;
  request.perception = &stages;
  request.time_s = 1.0 + k * kPeriodS;
  request.frame_time_s = kPeriodS;
  request.gaze = GazePoint{0.4, 0.45};
  request.field_cd_m2 = mean_luminance(scene);
  return request;
}

EyeFrame frame_at(FrameEngine& engine, const ImageRGBA& scene, const PerceptionSettings& stages, int k) {
  return engine.frame(request_at(scene, stages, k));
}

class FrameEngineGlTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      context_ = gl::create_compute_context();
    } catch (const DisplayError& error) {
      skip_reason_ = error.what();
    }
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override {
    if (!context_) GTEST_SKIP() << "no OpenGL 4.5 context here: " << skip_reason_;
  }
  static std::unique_ptr<DisplayBackend> context_;
  static std::string skip_reason_;
};
std::unique_ptr<DisplayBackend> FrameEngineGlTest::context_;
std::string FrameEngineGlTest::skip_reason_;

TEST(FrameEngine, EveryCpuBackendBringsTheCpuEngine) {
  for (const GlareBackendRequest backend : {GlareBackendRequest::cpu, GlareBackendRequest::automatic}) {
    // No GL context factory: "auto" takes the planned float32 path, "cpu" the float64 reference.
    FrameEngine engine(glare_spec(backend), AdaptationTimeConstants{}, display_spec(), 3, {});
    EXPECT_EQ(engine.kind(), FrameEngineKind::cpu);
    EXPECT_NE(engine.reason().find("frame engine cpu: glare backend cpu float"), std::string::npos) << engine.reason();
  }
}

TEST_F(FrameEngineGlTest, TheGlBackendBringsTheGlEngine) {
  FrameEngine engine(glare_spec(GlareBackendRequest::gl), AdaptationTimeConstants{}, display_spec(), 3,
                     gl::compute_context_factory());
  EXPECT_EQ(engine.kind(), FrameEngineKind::gl);
  EXPECT_NE(engine.reason().find("frame engine gl: glare backend gl"), std::string::npos) << engine.reason();
}

// Every stage on (adaptation from a brighter room, static glare, acuity, tone mapping, scotopic
// colour), three frames in a row: each GL frame equals the CPU frame within 1e-3 relative (1e-3
// cd/m2 below 1 cd/m2), and both eyes adapt alike. A perturbed GL frame is caught by the bound.
TEST_F(FrameEngineGlTest, GlEngineFramesEqualTheCpuEnginesWithEveryStage) {
  const ImageRGBA scene = night_scene();
  PerceptionSettings stages;  // every stage on by default
  ASSERT_TRUE(stages.adaptation && stages.acuity && stages.tone_mapping && stages.scotopic);
  FrameEngine cpu(glare_spec(GlareBackendRequest::cpu), AdaptationTimeConstants{}, display_spec(), 3, {});
  FrameEngine gl(glare_spec(GlareBackendRequest::gl), AdaptationTimeConstants{}, display_spec(), 3,
                 gl::compute_context_factory());
  ASSERT_EQ(gl.kind(), FrameEngineKind::gl);
  const auto worst_error = [](const ImageRGBA& got, const ImageRGBA& reference) {
    double worst = 0.0;
    for (std::size_t i = 0; i < reference.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      const double scale = std::max(1.0, std::abs(static_cast<double>(reference.rgba[i])));
      worst = std::max(worst, std::abs(static_cast<double>(got.rgba[i]) - reference.rgba[i]) / scale);
    }
    return worst;
  };
  for (int k = 0; k < 3; ++k) {
    const EyeFrame reference = frame_at(cpu, scene, stages, k);
    const EyeFrame frame = frame_at(gl, scene, stages, k);
    ASSERT_EQ(frame.reports.size(), 1u);
    ASSERT_EQ(reference.reports.size(), 1u);
    EXPECT_TRUE(frame.reports.front().convolved);
    // The pupil follows the adapted luminance, which the GL pyramid sums in float.
    EXPECT_NEAR(frame.reports.front().pupil_diameter_mm / reference.reports.front().pupil_diameter_mm, 1.0, 1e-6);
    EXPECT_NEAR(*frame.adapted_luminance_cd_m2 / *reference.adapted_luminance_cd_m2, 1.0, 1e-4);
    const double error = worst_error(frame.image_cd_m2, reference.image_cd_m2);
    std::printf("frame %d: L_i %.6g cd/m2, GL against CPU worst relative error %.2e\n", k,
                *reference.adapted_luminance_cd_m2, error);
    EXPECT_LT(error, 1e-3) << "frame " << k;
    // The bound sees a wrong frame: the GL frame 1 % brighter at the lamp fails it.
    ImageRGBA perturbed = frame.image_cd_m2;
    float* lamp = perturbed.pixel(51, 41);
    lamp[1] *= 1.01f;
    EXPECT_GT(worst_error(perturbed, reference.image_cd_m2), 1e-3);
  }
}

TEST_F(FrameEngineGlTest, FramesKeptOnTheGpuWithTheirScenesFactsEqualTheCpuEngines) {
  // A session's requests: the frame left on the GPU, each seen image with its facts kept from frame
  // to frame (the GL stages upload a scene once under its facts' token). Scene A, A, B, A: each GL
  // frame, read back here, against the CPU engine's frame of the same request.
  const ImageRGBA scene_a = night_scene();
  ImageRGBA scene_b = scene_a;
  for (int y = 40; y < 43; ++y)
    for (int x = 50; x < 53; ++x) {
      float* moved = scene_b.pixel(x + 60, y + 20);
      const float* lamp = scene_a.pixel(x, y);
      std::copy(lamp, lamp + 3, moved);
      std::copy(scene_a.pixel(0, 0), scene_a.pixel(0, 0) + 3, scene_b.pixel(x, y));
    }
  const PerceptionSettings stages;
  FrameEngine cpu(glare_spec(GlareBackendRequest::cpu), AdaptationTimeConstants{}, display_spec(), 3, {});
  FrameEngine gl(glare_spec(GlareBackendRequest::gl), AdaptationTimeConstants{}, display_spec(), 3,
                 one_context_factory(*context_));
  ASSERT_EQ(gl.kind(), FrameEngineKind::gl);
  FrameFacts cpu_facts_a, cpu_facts_b, gl_facts_a, gl_facts_b;
  const auto request_for = [&](const ImageRGBA& scene, FrameFacts& facts, int k, bool on_gpu) {
    EyeFrameRequest request = request_at(scene, stages, k);
    request.facts = &facts;
    request.on_gpu = on_gpu;
    return request;
  };
  const bool scene_is_b[] = {false, false, true, false};
  double worst_between_scenes = 0.0;
  for (int k = 0; k < 4; ++k) {
    const ImageRGBA& scene = scene_is_b[k] ? scene_b : scene_a;
    const EyeFrame reference = cpu.frame(request_for(scene, scene_is_b[k] ? cpu_facts_b : cpu_facts_a, k, false));
    const EyeFrame frame = gl.frame(request_for(scene, scene_is_b[k] ? gl_facts_b : gl_facts_a, k, true));
    ASSERT_TRUE(frame.gpu_image_cd_m2) << "frame " << k;
    const ImageRGBA image = frame.gpu_image_cd_m2->download();
    double worst = 0.0, between = 0.0;
    for (std::size_t i = 0; i < reference.image_cd_m2.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      const double value = reference.image_cd_m2.rgba[i];
      const double scale = std::max(1.0, std::abs(value));
      worst = std::max(worst, std::abs(image.rgba[i] - value) / scale);
      between = std::max(between, static_cast<double>(std::abs(scene_a.rgba[i] - scene_b.rgba[i]) / std::max(1.0f, scene_a.rgba[i])));
    }
    std::printf("scene %c, frame %d: GL on the GPU against CPU worst relative error %.2e\n", scene_is_b[k] ? 'B' : 'A',
                k, worst);
    EXPECT_LT(worst, 1e-3) << "frame " << k;
    worst_between_scenes = std::max(worst_between_scenes, between);
  }
  EXPECT_NE(gl_facts_a.gpu_scene_token, 0u);
  EXPECT_NE(gl_facts_a.gpu_scene_token, gl_facts_b.gpu_scene_token);
  EXPECT_GT(worst_between_scenes, 1.0);  // a stale scene would show
}

}  // namespace
}  // namespace glarelab
