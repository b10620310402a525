#include "stimuli/frame_engine_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "stimuli/frame_engine.h"
#include "stimuli/perception/stage_timing.h"

namespace glarelab {
namespace {

// The display of the perception rows (stage_timing.h): 41.9 px/deg at the centre, peak 250 cd/m2.
DisplaySpec bench_display(int width_px, int height_px) {
  DisplaySpec display;
  display.width_px = width_px;
  display.height_px = height_px;
  display.viewing_distance_mm = 600.0;
  display.pixel_pitch_mm = 0.25;
  display.peak_luminance_cd_m2 = 250.0;
  return display;
}

GlareSpec bench_glare(GlareBackendRequest backend) {
  GlareSpec spec;
  spec.grid_px = 256;
  spec.wavelength_samples = 16;
  spec.skip_invisible = false;
  spec.backend = backend;
  return spec;
}

// ||actual - expected|| / ||expected|| over the R, G and B of every pixel.
double relative_l2(const ImageRGBA& actual, const ImageRGBA& expected) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    const double e = expected.rgba[i], d = static_cast<double>(actual.rgba[i]) - e;
    difference += d * d;
    norm += e * e;
  }
  return norm > 0.0 ? std::sqrt(difference / norm) : std::sqrt(difference);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

FrameEngineBenchmarkResult run_frame_engine_benchmark(const FrameEngineBenchmarkOptions& options) {
  if (options.repeats < 1) throw std::invalid_argument("frame engine benchmark: repeats must be at least 1");
  const DisplaySpec display = bench_display(options.width_px, options.height_px);
  const ImageRGBA scene = perception_test_frame(options.width_px, options.height_px);
  const PerceptionSettings stages;  // every stage on
  FrameEngineBenchmarkResult result;
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  result.floor_cd_m2 = 1e-4 * display.peak_luminance_cd_m2;
  std::optional<ImageRGBA> reference;
  const auto run = [&](GlareBackendRequest backend, const GlContextFactory& gl_context, int repeats) {
    FrameEngine engine(bench_glare(backend), AdaptationTimeConstants{}, display, 1, gl_context);
    FrameEngineBenchmarkRow row;
    row.engine = std::string(spelling(engine.kind()));
    row.reason = engine.reason();
    ImageRGBA first;
    for (int k = 0; k <= repeats; ++k) {
      EyeFrameRequest request(scene);
      request.mode = GlareMode::static_eye;
      request.glared = true;
      request.perception = &stages;
      request.time_s = 1.0 + k / 90.0;
      request.frame_time_s = 1.0 / 90.0;
      const auto start = std::chrono::steady_clock::now();
      EyeFrame frame = engine.frame(request);
      const double took_s = seconds_since(start);
      if (k == 0) {
        row.first_frame_s = took_s;
        first = std::move(frame.image_cd_m2);
      } else {
        row.fastest_frame_s = k == 1 ? took_s : std::min(row.fastest_frame_s, took_s);
      }
    }
    if (reference) {
      row.max_relative_error = max_relative_pixel_error(first, *reference, result.floor_cd_m2);
      row.relative_l2_error = relative_l2(first, *reference);
    } else {
      reference = std::move(first);
    }
    if (options.progress)
      options.progress("frame engine " + row.engine + ": first frame " + std::to_string(1e3 * row.first_frame_s) +
                       " ms, fastest " + std::to_string(1e3 * row.fastest_frame_s) + " ms");
    return row;
  };
  // The reference: the CPU engine with the float64 glare (its first frame only).
  const auto reference_row = run(GlareBackendRequest::cpu, {}, 0);
  result.reference_s = reference_row.first_frame_s;
  // No GL context: the CPU engine, the glare on the planned float32 path, as sessions run it.
  result.rows.push_back(run(GlareBackendRequest::automatic, {}, options.repeats));
  if (options.gl_context) result.rows.push_back(run(GlareBackendRequest::gl, options.gl_context, options.repeats));
  return result;
}

std::string format_frame_engine_benchmark(const FrameEngineBenchmarkResult& result) {
  std::string text =
      "| engine | first frame ms | fastest frame ms | relative L2 error | max per-pixel relative error |\n"
      "|---|---|---|---|---|\n";
  char line[256];
  for (const FrameEngineBenchmarkRow& row : result.rows) {
    std::snprintf(line, sizeof line, "| %s | %.1f | %.1f | %.2e | %.2e |\n", row.engine.c_str(),
                  1e3 * row.first_frame_s, 1e3 * row.fastest_frame_s, row.relative_l2_error, row.max_relative_error);
    text += line;
  }
  char tail[200];
  std::snprintf(tail, sizeof tail,
                "\n%d x %d, per-pixel error floor %.3g cd/m2; the reference (the cpu engine, float64 glare) "
                "took %.1f ms a frame.\n",
                result.width_px, result.height_px, result.floor_cd_m2, 1e3 * result.reference_s);
  text += tail;
  for (const FrameEngineBenchmarkRow& row : result.rows) text += row.reason + "\n";
  return text;
}

}  // namespace glarelab
