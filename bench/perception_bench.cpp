// The perception stages of Luidolt 2020 (stimuli/perception/) on the CPU in double precision, one
// 1920 x 1080 frame per iteration: a night scene (0.002-0.2 cd/m2 texture, most of it below
// L* = 1 and so blurred by the acuity stage) with lamps of 1e3-1e4 cd/m2.
//
// For scale, the thesis' GPU figures (section 7.5, Table 7.1: GeForce GTX 1070, Unreal Engine 4.20
// post-process passes, HTC Vive Pro at 1440 x 1600 per eye): temporal adaptation 0.18 ms, visual
// acuity reduction 0.36 ms, scotopic colours 0.14 ms per eye.
// These are a single-threaded reference, written to be checked, not to be fast; the counters give
// the separable blur's error against the 2D reference on this frame (L* units).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "core/random.h"
#include "core/streaming_floor.h"
#include "runner/display/compute_context.h"
#include "stimuli/perception/gl_perception_stages.h"
#include "stimuli/perception/lab_colour.h"
#include "stimuli/perception/acuity_loss_float.h"
#include "stimuli/perception/perception_stages.h"
#include "stimuli/perception/perception_stages_float.h"
#include "stimuli/perception/stage_timing.h"

namespace glarelab {
namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;

const ImageRGBA& night_frame() {
  static const ImageRGBA frame = [] {
    const CounterRandom random(11, RandomStream::observer);
    ImageRGBA image(kWidth, kHeight, 0.0f);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const std::size_t k = static_cast<std::size_t>(y) * kWidth + x;
        float* p = image.pixel(x, y);
        const double base = 0.002 * std::pow(100.0, random.uniform(k));  // 0.002 .. 0.2 cd/m2
        p[0] = static_cast<float>(base * 0.9);
        p[1] = static_cast<float>(base);
        p[2] = static_cast<float>(base * 1.2);
        p[3] = 1.0f;
      }
    for (const auto& [cx, cy] : {std::pair{400, 300}, std::pair{1500, 250}, std::pair{960, 800}})
      for (int y = cy - 6; y < cy + 6; ++y)
        for (int x = cx - 6; x < cx + 6; ++x) {
          float* p = image.pixel(x, y);
          p[0] = p[1] = p[2] = cx == 960 ? 1e4f : 1e3f;
        }
    return image;
  }();
  return frame;
}

DisplaySpec bench_display() {
  DisplaySpec display;
  display.width_px = kWidth;
  display.height_px = kHeight;
  return display;  // 600 mm, 0.25 mm pitch: 41.9 px/deg
}

void BM_PerceptionAdaptation(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  TemporalAdaptation eye(1.0);
  for (auto _ : state) {
    const double frame_luminance = frame_adaptation_luminance_cd_m2(frame, 0.45, 0.4);
    benchmark::DoNotOptimize(eye.advance(frame_luminance, 1.0 / 90.0));
  }
  state.counters["adapted_cd_m2"] = eye.adapted_luminance_cd_m2();
}
BENCHMARK(BM_PerceptionAdaptation)->Unit(benchmark::kMillisecond);

void BM_PerceptionAcuitySeparable(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  const double ppd = display_pixels_per_degree(bench_display());
  for (auto _ : state) benchmark::DoNotOptimize(apply_acuity_loss(frame, AcuitySettings{}, ppd));
}
BENCHMARK(BM_PerceptionAcuitySeparable)->Unit(benchmark::kMillisecond);

void BM_PerceptionAcuity2dReference(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  const double ppd = display_pixels_per_degree(bench_display());
  for (auto _ : state) benchmark::DoNotOptimize(apply_acuity_loss_2d_reference(frame, AcuitySettings{}, ppd));
}
BENCHMARK(BM_PerceptionAcuity2dReference)->Unit(benchmark::kMillisecond);

// The separable blur's error against the 2D reference on this frame, in L* units (no timing loop
// of its own beyond one pass each).
void BM_PerceptionAcuitySeparableError(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  const double ppd = display_pixels_per_degree(bench_display());
  const AcuitySettings settings;
  std::vector<double> lightness(static_cast<std::size_t>(kWidth) * kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const float* p = frame.pixel(x, y);
      lightness[static_cast<std::size_t>(y) * kWidth + x] = rec709_to_lab(p[0], p[1], p[2], 100.0).lightness;
    }
  double max_error = 0.0, sum2 = 0.0;
  for (auto _ : state) {
    const std::vector<double> separable = blur_lightness_separable(lightness, kWidth, kHeight, settings, ppd);
    const std::vector<double> two_d = blur_lightness_2d(lightness, kWidth, kHeight, settings, ppd);
    max_error = 0.0;
    sum2 = 0.0;
    for (std::size_t i = 0; i < separable.size(); ++i) {
      const double e = std::abs(separable[i] - two_d[i]);
      max_error = std::max(max_error, e);
      sum2 += e * e;
    }
  }
  state.counters["max_abs_error_Lstar"] = max_error;
  state.counters["rms_error_Lstar"] = std::sqrt(sum2 / static_cast<double>(lightness.size()));
}
BENCHMARK(BM_PerceptionAcuitySeparableError)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_PerceptionToneMapping(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  ToneMappingSettings settings;
  settings.curve = state.range(0) == 0 ? ToneCurve::aces_narkowicz : ToneCurve::aces_hill;
  for (auto _ : state) benchmark::DoNotOptimize(tone_map(frame, 0.05, settings, 250.0));
  state.SetLabel(settings.curve == ToneCurve::aces_narkowicz ? "aces_narkowicz" : "aces_hill");
}
BENCHMARK(BM_PerceptionToneMapping)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_PerceptionScotopic(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  const ScotopicForm form = state.range(0) == 0 ? ScotopicForm::luidolt_tint : ScotopicForm::spencer_desaturation;
  ScotopicSettings settings;
  settings.form = form;
  for (auto _ : state) benchmark::DoNotOptimize(apply_scotopic_colour(frame, 0.6, settings));
  state.SetLabel(form == ScotopicForm::luidolt_tint ? "luidolt_tint" : "spencer_desaturation");
}
BENCHMARK(BM_PerceptionScotopic)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_PerceptionAllStages(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  const DisplaySpec display = bench_display();
  const PerceptionSettings settings;
  TemporalAdaptation eye(1.0);
  for (auto _ : state)
    benchmark::DoNotOptimize(run_perception_stages(frame, {0.45, 0.4, 1.0 / 90.0}, eye, settings, display));
}
BENCHMARK(BM_PerceptionAllStages)->Unit(benchmark::kMillisecond);

// The float32 stages sessions run (stimuli/perception/perception_stages_float.h), one per hardware
// thread, beside the streaming floors they are measured against (core/streaming_floor.h): reading
// the frame (adaptation) and reading and writing it (the others). `glarelab bench` prints the same
// pairs with their errors (stimuli/cpu_stage_benchmark.h).
void BM_PerceptionFloatAdaptation(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  for (auto _ : state)
    benchmark::DoNotOptimize(frame_adaptation_luminance_float_cd_m2(frame, 0.45, 0.4, {}, perception_float_threads()));
}
BENCHMARK(BM_PerceptionFloatAdaptation)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionFloatAcuity(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  ImageRGBA work = frame;
  const double ppd = display_pixels_per_degree(bench_display());
  for (auto _ : state) {
    state.PauseTiming();
    std::copy(frame.rgba.begin(), frame.rgba.end(), work.rgba.begin());
    state.ResumeTiming();
    apply_acuity_loss_float(work, AcuitySettings{}, ppd, perception_float_threads());
  }
}
BENCHMARK(BM_PerceptionFloatAcuity)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionFloatToneMapping(benchmark::State& state) {
  ImageRGBA work = night_frame();
  ToneMappingSettings settings;
  settings.curve = state.range(0) == 0 ? ToneCurve::aces_narkowicz : ToneCurve::aces_hill;
  // In place on its own output: the curve's cost does not depend on the values it meets.
  for (auto _ : state) tone_map_float(work, 0.05, settings, 250.0, perception_float_threads());
}
BENCHMARK(BM_PerceptionFloatToneMapping)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionFloatScotopic(benchmark::State& state) {
  ImageRGBA work = night_frame();
  ScotopicSettings settings;
  settings.form = state.range(0) == 0 ? ScotopicForm::luidolt_tint : ScotopicForm::spencer_desaturation;
  for (auto _ : state) apply_scotopic_colour_float(work, 0.5, settings, perception_float_threads());
}
BENCHMARK(BM_PerceptionFloatScotopic)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionFloatAllStages(benchmark::State& state) {
  const ImageRGBA& frame = night_frame();
  TemporalAdaptation eye(1.0);
  for (auto _ : state)
    benchmark::DoNotOptimize(
        run_perception_stages_float(frame, {0.45, 0.4, 1.0 / 90.0}, eye, PerceptionSettings{}, bench_display()));
}
BENCHMARK(BM_PerceptionFloatAllStages)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg 0: read the frame (the adaptation's floor); 1: read and write it (the other stages').
void BM_PerceptionStreamingFloor(benchmark::State& state) {
  const std::size_t frame_bytes = 16 * static_cast<std::size_t>(kWidth) * kHeight;
  StreamingFloor floor(frame_bytes, state.range(0) == 0 ? 0 : frame_bytes, perception_float_threads());
  for (auto _ : state) floor.run_s();
}
BENCHMARK(BM_PerceptionStreamingFloor)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace glarelab

// The GL stages (stimuli/perception/gl_*.h) on the same frame, on the compute context's renderer
// (llvmpipe here, so these are CPU figures too), wall-clock time with glFinish: the work done, not
// queued. Buffers stay on the GPU between iterations except in BM_PerceptionGlAllStages (one upload
// and one read-back per frame, as a session would). Counter max_relative_error: GL against the CPU
// double stage on the same input (per pixel, relative to the pixel's largest channel, floor 1e-6
// cd/m2 scene-referred, 1e-4 of the peak display-referred; stimuli/perception/stage_timing.h);
// thesis_gtx1070_ms: Table 7.1 per eye at 1440 x 1600. Each stage runs once before timing (llvmpipe
// compiles a shader on its first dispatch).
namespace glarelab {
namespace {

constexpr double kBenchPeak = 250.0;

DisplayBackend& gl_context() {
  static const std::unique_ptr<DisplayBackend> backend = gl::create_compute_context();
  return *backend;
}

void BM_PerceptionGlAdaptation(benchmark::State& state) {
  gl_context().make_current();
  const ImageRGBA& frame = night_frame();
  gl::GlFrameBuffer buffer(frame);
  gl::GlFrameAdaptationLuminance stage;
  TemporalAdaptation eye(1.0);
  double luminance = stage.luminance_cd_m2(buffer, 0.45, 0.4);  // warm-up: llvmpipe compiles on first use
  for (auto _ : state) {
    luminance = stage.luminance_cd_m2(buffer, 0.45, 0.4);  // reads the top level back: synchronous
    benchmark::DoNotOptimize(eye.advance(luminance, 1.0 / 90.0));
  }
  const double cpu = frame_adaptation_luminance_cd_m2(frame, 0.45, 0.4);
  state.counters["max_relative_error"] = std::abs(luminance - cpu) / cpu;
  state.counters["thesis_gtx1070_ms"] = 0.18;
}
BENCHMARK(BM_PerceptionGlAdaptation)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionGlAcuity(benchmark::State& state) {
  gl_context().make_current();
  const ImageRGBA& frame = night_frame();
  const double ppd = display_pixels_per_degree(bench_display());
  gl::GlFrameBuffer input(frame), output(kWidth, kHeight);
  gl::GlAcuityLoss stage;
  stage.apply(input, AcuitySettings{}, ppd, output);  // warm-up: llvmpipe compiles on first use
  glFinish();
  for (auto _ : state) {
    stage.apply(input, AcuitySettings{}, ppd, output);
    glFinish();
  }
  state.counters["max_relative_error"] =
      max_relative_pixel_error(output.download(), apply_acuity_loss(frame, AcuitySettings{}, ppd), 1e-6);
  state.counters["thesis_gtx1070_ms"] = 0.36;
}
BENCHMARK(BM_PerceptionGlAcuity)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionGlToneMapping(benchmark::State& state) {
  gl_context().make_current();
  const ImageRGBA& frame = night_frame();
  ToneMappingSettings settings;
  settings.curve = state.range(0) == 0 ? ToneCurve::aces_narkowicz : ToneCurve::aces_hill;
  gl::GlFrameBuffer input(frame), output(kWidth, kHeight);
  gl::GlToneMapping stage;
  stage.apply(input, 0.05, settings, kBenchPeak, output);  // warm-up
  glFinish();
  for (auto _ : state) {
    stage.apply(input, 0.05, settings, kBenchPeak, output);
    glFinish();
  }
  state.counters["max_relative_error"] =
      max_relative_pixel_error(output.download(), tone_map(frame, 0.05, settings, kBenchPeak), 1e-4 * kBenchPeak);
  state.SetLabel(to_string(settings.curve));
}
BENCHMARK(BM_PerceptionGlToneMapping)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionGlScotopic(benchmark::State& state) {
  gl_context().make_current();
  const ImageRGBA& frame = night_frame();
  ScotopicSettings settings;
  settings.form = state.range(0) == 0 ? ScotopicForm::luidolt_tint : ScotopicForm::spencer_desaturation;
  gl::GlFrameBuffer input(frame), output(kWidth, kHeight);
  gl::GlScotopicColour stage;
  stage.apply(input, 0.6, settings, output);  // warm-up
  glFinish();
  for (auto _ : state) {
    stage.apply(input, 0.6, settings, output);
    glFinish();
  }
  state.counters["max_relative_error"] =
      max_relative_pixel_error(output.download(), apply_scotopic_colour(frame, 0.6, settings), 1e-4 * kBenchPeak);
  state.counters["thesis_gtx1070_ms"] = 0.14;
  state.SetLabel(to_string(settings.form));
}
BENCHMARK(BM_PerceptionGlScotopic)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PerceptionGlAllStages(benchmark::State& state) {
  gl_context().make_current();
  const ImageRGBA& frame = night_frame();
  const DisplaySpec display = bench_display();
  const PerceptionSettings settings;
  gl::GlPerceptionStages stages;
  TemporalAdaptation eye(1.0), cpu_eye(1.0);
  PerceptionResult result = stages.run(frame, {0.45, 0.4, 1.0 / 90.0}, eye, settings, display);  // warm-up
  for (auto _ : state) {
    eye = TemporalAdaptation(1.0);
    result = stages.run(frame, {0.45, 0.4, 1.0 / 90.0}, eye, settings, display);  // reads the frame back
  }
  const PerceptionResult cpu = run_perception_stages(frame, {0.45, 0.4, 1.0 / 90.0}, cpu_eye, settings, display);
  state.counters["max_relative_error"] =
      max_relative_pixel_error(result.image, cpu.image, 1e-4 * display.peak_luminance_cd_m2);
}
BENCHMARK(BM_PerceptionGlAllStages)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace glarelab
