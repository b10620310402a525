#include "stimuli/depth_of_field_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <sstream>

#include "core/display_spec.h"
#include "glare/refraction/dioptric_power.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

constexpr int kWidth = kDepthBenchWidthPx;
constexpr int kHeight = kDepthBenchHeightPx;

}  // namespace

const DepthBenchScene& depth_of_field_bench_scene() {
  static const DepthBenchScene scene = [] {
    DepthBenchScene s;
    s.image = ImageRGBA(kWidth, kHeight, 1.0f);
    s.depth_m.assign(static_cast<std::size_t>(kWidth) * kHeight, 4.0f);
    const int horizon = kHeight / 2;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        float* p = s.image.pixel(x, y);
        const double checker = ((x / 16 + y / 16) % 2 == 0) ? 80.0 : 20.0;
        p[0] = static_cast<float>(checker + 15.0 * std::sin(0.31 * x) * std::cos(0.17 * y));
        p[1] = static_cast<float>(0.8 * checker + 10.0 * std::sin(0.05 * x + 0.07 * y));
        p[2] = static_cast<float>(0.6 * checker);
        if (y > horizon) {  // the floor: vergence linear in the row, 0.25 D at the horizon to 2.22 D
          const double t = static_cast<double>(y - horizon) / (kHeight - 1 - horizon);
          s.depth_m[static_cast<std::size_t>(y) * kWidth + x] =
              static_cast<float>(1.0 / (0.25 + t * (1.0 / 0.45 - 0.25)));
        }
      }
    const struct {
      int x0, y0, x1, y1;
      float depth_m, luminance;
    } boards[] = {
        {80, 120, 360, 520, 1.5f, 150.0f}, {420, 200, 700, 600, 0.6f, 60.0f}, {650, 420, 980, 740, 0.4f, 200.0f}};
    for (const auto& board : boards)
      for (int y = board.y0; y < board.y1; ++y)
        for (int x = board.x0; x < board.x1; ++x) {
          float* p = s.image.pixel(x, y);
          const float stripe = ((x / 6) % 2 == 0) ? 1.0f : 0.3f;
          p[0] = p[1] = p[2] = board.luminance * stripe;
          s.depth_m[static_cast<std::size_t>(y) * kWidth + x] = board.depth_m;
        }
    return s;
  }();
  return scene;
}

DepthOfFieldSettings depth_of_field_bench_settings(int threads) {
  DisplaySpec display;
  display.width_px = kWidth;
  display.height_px = kHeight;
  DepthOfFieldSettings settings;
  settings.degrees_per_pixel = DisplayModel(display).degrees_per_pixel_at_centre();
  settings.pupil_radius_m = 0.002;
  const DioptricPower cylinder = DioptricPower::from_prescription({0.0, -0.5, 20.0});
  settings.residual_error = [cylinder](double distance_m) {
    return DioptricPower::spherical(1.0 / 0.6 - 1.0 / distance_m) + cylinder;
  };
  settings.threads = threads;
  return settings;
}

DepthOfFieldBenchmarkResult run_depth_of_field_benchmark(int threads, int repeats) {
  const DepthBenchScene& scene = depth_of_field_bench_scene();
  const DepthOfFieldSettings settings = depth_of_field_bench_settings(threads);
  DepthOfFieldBenchmarkResult result;
  result.threads = threads;
  result.tolerance_px = settings.tolerance_px;
  ImageRGBA blurred;
  result.fastest_ms = 1e300;
  for (int k = 0; k < std::max(repeats, 1); ++k) {
    const auto start = std::chrono::steady_clock::now();
    blurred = apply_depth_of_field(scene.image, scene.depth_m, settings, &result.report);
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - start;
    result.fastest_ms = std::min(result.fastest_ms, took.count());
  }
  const auto start = std::chrono::steady_clock::now();
  const ImageRGBA reference = depth_of_field_reference(scene.image, scene.depth_m, depth_of_field_bench_settings(1));
  result.reference_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.error = depth_of_field_error(blurred, reference);
  return result;
}

std::string format_depth_of_field_benchmark(const DepthOfFieldBenchmarkResult& result) {
  std::ostringstream out;
  out << "| frame | threads | tolerance px | layers (blurred: direct + FFT) | frame ms | mean error / mean | "
         "mean error cd/m2 | max error cd/m2 | per-pixel reference s |\n"
         "|---|---|---|---|---|---|---|---|---|\n";
  out << "| " << kWidth << " x " << kHeight << " with Z | " << result.threads << " | " << result.tolerance_px << " | "
      << result.report.layers << " (" << result.report.blurred_layers << ": " << result.report.direct_layers << " + "
      << result.report.fft_layers << ") | " << std::fixed << std::setprecision(1) << result.fastest_ms << " | "
      << std::setprecision(4) << result.error.mean_relative << " | " << std::setprecision(3) << result.error.mean_abs_cd_m2
      << " | " << std::setprecision(1) << result.error.max_abs_cd_m2 << " | " << std::setprecision(2) << result.reference_s
      << " |\n";
  return out.str();
}

}  // namespace glarelab
