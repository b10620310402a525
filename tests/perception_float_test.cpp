// The float32, threaded perception stages (stimuli/perception/perception_stages_float.h) against
// their float64 references, stage by stage and as the whole chain, on a frame of hard cases: a
// 1e6 cd/m2 lamp beside 0.01 cd/m2, zeros, one-pixel lines at the frame's edges, dark saturated
// colours. The metric is the bench's (stimuli/perception/stage_timing.h): per pixel, the largest
// channel error over the pixel's largest channel, floored at 1e-6 cd/m2 (scene-referred) or 1e-4 of
// the display peak (display-referred); the bound is 1e-5.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "core/random.h"
#include "core/streaming_floor.h"
#include "glare/eye/pupil_model.h"
#include "stimuli/perception/acuity_loss.h"
#include "stimuli/perception/acuity_loss_float.h"
#include "stimuli/perception/perception_stages.h"
#include "stimuli/perception/perception_stages_float.h"
#include "stimuli/perception/stage_timing.h"

namespace glarelab {
namespace {

constexpr double kBound = 1e-5;
constexpr double kSceneFloorCdM2 = 1e-6;

// 97 x 61 (odd sizes: the thread chunks split unevenly): a dark textured street from 0.002 to
// 0.05 cd/m2 (L* < 1: the acuity blur's support) with coloured noise, a brighter half up to
// 300 cd/m2, a 1e6 cd/m2 lamp beside a 0.01 cd/m2 patch, a block of zeros, dark saturated
// primaries, and one-pixel lines of 5e3 cd/m2 along the top row and the right column.
ImageRGBA hard_frame() {
  ImageRGBA frame(97, 61, 0.0f);
  const CounterRandom rng(20261129, RandomStream::glare_gl_test_input);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      float* p = frame.pixel(x, y);
      const std::uint64_t i = static_cast<std::uint64_t>(y) * frame.width_px + x;
      const double base = x < 60 ? 0.002 * std::pow(25.0, rng.uniform(3 * i)) : 0.5 * std::pow(600.0, rng.uniform(3 * i));
      p[0] = static_cast<float>(base * (0.6 + 0.8 * rng.uniform(3 * i + 1)));
      p[1] = static_cast<float>(base);
      p[2] = static_cast<float>(base * (0.6 + 0.8 * rng.uniform(3 * i + 2)));
      p[3] = 1.0f;
    }
  for (int y = 20; y < 23; ++y)
    for (int x = 30; x < 33; ++x) {
      float* p = frame.pixel(x, y);
      p[0] = p[1] = p[2] = 1e6f;
      for (int c = 0; c < 3; ++c) frame.pixel(x + 3, y)[c] = 0.01f;
    }
  for (int y = 40; y < 46; ++y)
    for (int x = 10; x < 18; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 0.0f;
  for (int k = 0; k < 3; ++k)  // dark saturated red, green and blue: Lab's X and Z off the linear branch
    for (int x = 40; x < 44; ++x) {
      float* p = frame.pixel(x, 50 + k);
      p[0] = p[1] = p[2] = 0.0f;
      p[k] = 0.015f;
    }
  for (int x = 0; x < frame.width_px; ++x) frame.pixel(x, 0)[0] = frame.pixel(x, 0)[1] = frame.pixel(x, 0)[2] = 5e3f;
  for (int y = 0; y < frame.height_px; ++y)
    frame.pixel(frame.width_px - 1, y)[0] = frame.pixel(frame.width_px - 1, y)[1] = frame.pixel(frame.width_px - 1, y)[2] = 5e3f;
  return frame;
}

TEST(PerceptionFloat, AdaptationLuminanceMatchesTheFloat64Reference) {
  const ImageRGBA frame = hard_frame();
  // Each form of the row sums this CPU runs (core/vector_isa.h).
  for (const VectorIsa isa : {VectorIsa::sse2, VectorIsa::avx2_fma}) {
    if (!vector_isa_available(isa)) continue;
    for (const double gaze_x : {0.5, 0.31, 0.02, 1.4, 40.0}) {  // 40 frame widths away: every weight underflows
      const double reference = frame_adaptation_luminance_cd_m2(frame, gaze_x, 0.35);
      for (const int threads : {1, 2, 3}) {
        const double fast = frame_adaptation_luminance_float_cd_m2(frame, gaze_x, 0.35, {}, threads, isa);
        EXPECT_NEAR(fast, reference, 1e-12 * reference)
            << "gaze x " << gaze_x << ", " << threads << " threads, form " << static_cast<int>(isa);
      }
    }
    // A uniform field adapts to its own luminance (section 5.1's weighted mean).
    const ImageRGBA uniform(1920, 1080, 10.0f);
    EXPECT_NEAR(frame_adaptation_luminance_float_cd_m2(uniform, 0.2, 0.9, {}, 2, isa), 10.0, 1e-12);
    const ImageRGBA small_uniform(33, 17, 10.0f);
    EXPECT_NEAR(frame_adaptation_luminance_float_cd_m2(small_uniform, 0.2, 0.9, {}, 2, isa), 10.0, 1e-12);
  }
  EXPECT_THROW(frame_adaptation_luminance_float_cd_m2(ImageRGBA{}, 0.5, 0.5, {}, 2), std::invalid_argument);
}

TEST(PerceptionFloat, AcuityMatchesTheFloat64ReferenceForEverySetting) {
  const ImageRGBA frame = hard_frame();
  for (const AcuitySigmaForm form : {AcuitySigmaForm::resolvable_frequency, AcuitySigmaForm::luidolt_linear})
    for (const SecondPassSigma second : {SecondPassSigma::filtered_lightness, SecondPassSigma::original_lightness})
      for (const double max_sigma_px : {1.0, 3.0})
        for (const double pixels_per_degree : {13.85, 41.9}) {
          AcuitySettings settings;
          settings.sigma_form = form;
          settings.second_pass = second;
          settings.max_sigma_px = max_sigma_px;
          const ImageRGBA reference = apply_acuity_loss(frame, settings, pixels_per_degree);
          // The case is not vacuous: the reference blurs the dark pixels well beyond the bound.
          ASSERT_GT(max_relative_pixel_error(reference, frame, kSceneFloorCdM2), 0.05);
          ImageRGBA fast = frame;
          apply_acuity_loss_float(fast, settings, pixels_per_degree, 2);
          const double error = max_relative_pixel_error(fast, reference, kSceneFloorCdM2);
          EXPECT_LE(error, kBound) << to_string(form) << ", max_sigma_px " << max_sigma_px << ", " << pixels_per_degree
                                   << " px/deg, second pass " << static_cast<int>(second);
          // Pixels the reference left untouched (L* >= 1) keep their exact bytes.
          for (std::size_t i = 0; i < frame.rgba.size(); ++i) {
            if (reference.rgba[i] == frame.rgba[i] && i % 4 != 3 && frame.rgba[i] > 1.0f) {
              ASSERT_EQ(fast.rgba[i], frame.rgba[i]) << "value " << i;
            }
          }
        }
}

TEST(PerceptionFloat, AcuityDoesNotDependOnTheThreadCount) {
  const ImageRGBA frame = hard_frame();
  ImageRGBA one = frame, three = frame;
  apply_acuity_loss_float(one, {}, 41.9, 1);
  apply_acuity_loss_float(three, {}, 41.9, 3);
  EXPECT_EQ(one.rgba, three.rgba);
  // Nor on the form of the rows' marking (stimuli/perception/acuity_marking.h), each this CPU runs;
  // 97 px wide, so every row ends in a part block.
  for (const VectorIsa isa : {VectorIsa::sse2, VectorIsa::avx2_fma}) {
    if (!vector_isa_available(isa)) continue;
    ImageRGBA form = frame;
    apply_acuity_loss_float(form, {}, 41.9, 2, isa);
    EXPECT_EQ(form.rgba, one.rgba) << "form " << static_cast<int>(isa);
  }
  ImageRGBA empty;
  EXPECT_THROW(apply_acuity_loss_float(empty, {}, 41.9, 2), std::invalid_argument);
  EXPECT_THROW(apply_acuity_loss_float(one, {}, 0.0, 2), std::invalid_argument);
}

TEST(PerceptionFloat, ToneMappingMatchesTheFloat64Reference) {
  const ImageRGBA frame = hard_frame();
  const double peak_cd_m2 = 250.0;
  for (const ToneCurve curve : {ToneCurve::aces_narkowicz, ToneCurve::aces_hill, ToneCurve::none})
    for (const double adapted_cd_m2 : {0.0, 0.03, 40.0, 1e5}) {
      ToneMappingSettings settings;
      settings.curve = curve;
      const ImageRGBA reference = tone_map(frame, adapted_cd_m2, settings, peak_cd_m2);
      ImageRGBA fast = frame;
      tone_map_float(fast, adapted_cd_m2, settings, peak_cd_m2, 2);
      EXPECT_LE(max_relative_pixel_error(fast, reference, 1e-4 * peak_cd_m2), kBound)
          << to_string(curve) << " at " << adapted_cd_m2 << " cd/m2";
    }
  ImageRGBA frame_copy = frame;
  EXPECT_THROW(tone_map_float(frame_copy, -1.0, {}, 250.0, 2), std::invalid_argument);
  EXPECT_THROW(tone_map_float(frame_copy, 1.0, {}, 0.0, 2), std::invalid_argument);
}

TEST(PerceptionFloat, ScotopicColourMatchesTheFloat64Reference) {
  ImageRGBA display_frame = hard_frame();
  tone_map_float(display_frame, 0.03, {}, 250.0, 2);  // display cd/m2, as the stage sees them
  for (const ScotopicForm form : {ScotopicForm::luidolt_tint, ScotopicForm::spencer_desaturation})
    for (const double rod_sensitivity : {0.0, 0.3, 1.0}) {
      ScotopicSettings settings;
      settings.form = form;
      const ImageRGBA reference = apply_scotopic_colour(display_frame, rod_sensitivity, settings);
      ImageRGBA fast = display_frame;
      apply_scotopic_colour_float(fast, rod_sensitivity, settings, 2);
      EXPECT_LE(max_relative_pixel_error(fast, reference, 1e-4 * 250.0), kBound)
          << to_string(form) << " at sigma " << rod_sensitivity;
    }
  EXPECT_THROW(apply_scotopic_colour_float(display_frame, 1.5, {}, 2), std::invalid_argument);
}

TEST(PerceptionFloat, WholeChainMatchesTheFloat64Reference) {
  const ImageRGBA frame = hard_frame();
  DisplaySpec display;
  PerceptionSettings settings;
  const PerceptionGlare veil = [](const ImageRGBA& image) {  // any operation on cd/m2
    ImageRGBA out = image;
    for (std::size_t i = 0; i < out.rgba.size(); i += 4)
      for (int c = 0; c < 3; ++c) out.rgba[i + c] = 0.9f * out.rgba[i + c] + 0.001f;
    return out;
  };
  TemporalAdaptation reference_eye(0.02), fast_eye(0.02);
  for (int frame_index = 0; frame_index < 3; ++frame_index) {
    const PerceptionFrameInput input{0.3, 0.4, 1.0 / 60.0};
    const PerceptionResult reference = run_perception_stages(frame, input, reference_eye, settings, display, veil);
    const PerceptionResult fast = run_perception_stages_float(frame, input, fast_eye, settings, display, veil, 2);
    EXPECT_EQ(fast.stages_run, reference.stages_run);
    EXPECT_NEAR(fast.adapted_luminance_cd_m2, reference.adapted_luminance_cd_m2, 1e-12 * reference.adapted_luminance_cd_m2);
    EXPECT_LE(max_relative_pixel_error(fast.image, reference.image, 1e-4 * display.peak_luminance_cd_m2), kBound)
        << "frame " << frame_index;
  }
}

TEST(PerceptionFloat, StreamingFloorReadsAndWritesEveryByte) {
  // Every float of the read buffer is 1: the checksum counts them, whatever the thread split.
  for (const int threads : {1, 2, 3}) {
    StreamingFloor floor(4 * 100003, 4 * 70001, threads);
    EXPECT_GE(floor.fastest_s(2), 0.0);
    EXPECT_EQ(floor.checksum(), 100003.0) << threads << " threads";
  }
  EXPECT_THROW(StreamingFloor(16, 16, 0), std::invalid_argument);
  EXPECT_THROW(StreamingFloor(0, 0, 2), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
