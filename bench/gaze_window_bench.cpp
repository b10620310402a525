// Gaze-contingent glare window (glare/cpu/gaze_window_convolution.h) against the full-frame CPU
// convolution: a 1024 x 1024 frame (one channel, double path), a 255 x 255 glare-like PSF (core
// plus 1/r^2 tail, reach 127 px), windows of 256 and 512 px around a gaze at (0.4, 0.45), with
// the exact apron (127 px) and with none. Counters: the FFT side, and the error of the blended
// frame against the full-frame convolution, as RMS relative to the full convolution's RMS, inside
// the window and outside it (outside, the blended frame is the unconvolved image: that error is
// the glare the window leaves out; the RMS is dominated by the lamps themselves, the mean of the
// per-pixel relative error is the typical pixel); and the largest relative difference of the windowed
// convolution, before blending, from the full one inside the window.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "glare/cpu/gaze_window_convolution.h"
#include "core/random.h"

namespace glarelab {
namespace {

constexpr int kSize = 1024;
constexpr int kPsfSize = 255;

const Psf& bench_psf() {
  static const Psf psf = [] {
    Psf p;
    p.size_px = kPsfSize;
    p.degrees_per_pixel = 0.02;
    p.values.resize(static_cast<std::size_t>(kPsfSize) * kPsfSize);
    double sum = 0.0;
    for (int y = 0; y < kPsfSize; ++y)
      for (int x = 0; x < kPsfSize; ++x) {
        const double r2 = (x - kPsfSize / 2.0 + 0.5) * (x - kPsfSize / 2.0 + 0.5) +
                          (y - kPsfSize / 2.0 + 0.5) * (y - kPsfSize / 2.0 + 0.5);
        p.at(0, x, y) = std::exp(-r2 / 2.0) + 1e-3 / (1.0 + r2);
        sum += p.at(0, x, y);
      }
    for (double& v : p.values) v /= sum;
    return p;
  }();
  return psf;
}

// A dim scene (0.1..1.1) with a few 1e4 lamps, one near the gaze.
const std::vector<double>& bench_plane() {
  static const std::vector<double> plane = [] {
    const CounterRandom random(9, RandomStream::observer);
    std::vector<double> p(static_cast<std::size_t>(kSize) * kSize);
    for (std::size_t k = 0; k < p.size(); ++k) p[k] = 0.1 + random.uniform(k);
    for (const auto& [x, y] : {std::pair{420, 470}, std::pair{100, 900}, std::pair{900, 120}, std::pair{700, 700}})
      p[static_cast<std::size_t>(y) * kSize + x] = 1e4;
    return p;
  }();
  return plane;
}

const std::vector<double>& full_convolution() {
  static const std::vector<double> full = convolve_plane_cpu(bench_plane(), kSize, kSize, bench_psf(), 0, {});
  return full;
}

void BM_FullFrameConvolution(benchmark::State& state) {
  ConvolutionReport report;
  for (auto _ : state) {
    auto out = convolve_plane_cpu(bench_plane(), kSize, kSize, bench_psf(), 0, {}, &report);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["fft_side"] = report.fft_cols;
}
BENCHMARK(BM_FullFrameConvolution)->Unit(benchmark::kMillisecond)->Iterations(3);

// range(0): window side; range(1): 1 = exact apron, 0 = none.
void BM_GazeWindowConvolution(benchmark::State& state) {
  GazeWindowOptions options;
  options.window_px = static_cast<int>(state.range(0));
  options.apron_px = state.range(1) != 0 ? -1 : 0;
  const auto& plane = bench_plane();
  const GazeWindow window = place_gaze_window(kSize, kSize, 0.4, 0.45, kPsfSize, options);
  ConvolutionReport report;
  std::vector<double> blended, windowed;
  for (auto _ : state) {
    windowed = convolve_gaze_window_plane(plane, kSize, kSize, bench_psf(), 0, window, {}, &report);
    blended = blend_gaze_window_plane(plane, kSize, kSize, windowed, window);
    benchmark::DoNotOptimize(blended.data());
  }
  const auto& full = full_convolution();
  // Exactness of the windowed convolution itself (before blending), largest relative difference.
  double window_error = 0.0;
  for (int y = 0; y < window.height_px; ++y)
    for (int x = 0; x < window.width_px; ++x) {
      const double reference = full[static_cast<std::size_t>(window.y0_px + y) * kSize + (window.x0_px + x)];
      window_error = std::max(window_error,
                              std::abs(windowed[static_cast<std::size_t>(y) * window.width_px + x] - reference) / reference);
    }
  double inside_error = 0.0, inside_norm = 0.0, outside_error = 0.0, outside_norm = 0.0;
  double outside_relative_sum = 0.0;
  std::size_t outside_pixels = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * kSize + x;
      const double error = blended[k] - full[k];
      if (window.contains(x, y)) {
        inside_error += error * error;
        inside_norm += full[k] * full[k];
      } else {
        outside_error += error * error;
        outside_norm += full[k] * full[k];
        outside_relative_sum += std::abs(error) / full[k];
        ++outside_pixels;
      }
    }
  state.counters["fft_side"] = report.fft_cols;
  state.counters["max_rel_error_window"] = window_error;
  state.counters["rms_rel_error_inside"] = std::sqrt(inside_error / inside_norm);
  state.counters["rms_rel_error_outside"] = std::sqrt(outside_error / outside_norm);
  state.counters["mean_rel_error_outside"] = outside_relative_sum / static_cast<double>(outside_pixels);
}
BENCHMARK(BM_GazeWindowConvolution)
    ->Args({256, 1})
    ->Args({256, 0})
    ->Args({512, 1})
    ->Args({512, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
}  // namespace glarelab
