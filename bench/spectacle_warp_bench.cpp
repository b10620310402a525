// A 1024 x 768 frame (0.03 deg per pixel: 600 mm away at 0.31 mm pitch, 30.7 x 23 deg) warped
// through spectacle lenses (stimuli/spectacle_warp.h): the grid trace alone (three wavelengths) and
// the whole warp (grid trace, interpolation, bilinear resampling of three channels), single-threaded.
// The per-pixel trace it is compared with takes about a second per channel.
// Counters: the grid's largest and mean interpolation error against tracing every pixel (pixels,
// green channel), computed once per lens outside the timed loop.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <utility>

#include "core/parallel_for.h"
#include "core/random.h"
#include "core/streaming_floor.h"
#include "glare/refraction/spectacle_lens.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {
namespace {

constexpr int kWidth = 1024;
constexpr int kHeight = 768;
const SpectacleFrame kFrame{kWidth, kHeight, 0.03};

SpectacleLensSpec bench_lens(int which) {
  SpectacleLensSpec spec;
  switch (which) {
    case 0: spec.prescription = {-6.0, 0.0, 0.0}; break;
    case 1: spec.prescription = {2.0, -1.5, 30.0}; break;
    default:
      spec.prescription = {1.0, 0.0, 0.0};
      spec.near_add_dioptres = 2.5;
      break;
  }
  return spec;
}

const char* lens_label(int which) { return which == 0 ? "-6.00 DS" : which == 1 ? "+2.00/-1.50x30" : "+1.00 add 2.50"; }

const ImageRGBA& scene() {
  static const ImageRGBA image = [] {
    const CounterRandom random(5, RandomStream::observer);
    ImageRGBA out(kWidth, kHeight, 0.0f);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        float* p = out.pixel(x, y);
        const double base = 100.0 * random.uniform(static_cast<std::size_t>(y) * kWidth + x);
        p[0] = static_cast<float>(base);
        p[1] = static_cast<float>(0.8 * base);
        p[2] = static_cast<float>(0.6 * base);
        p[3] = 1.0f;
      }
    return out;
  }();
  return image;
}

// Largest and mean |grid - per-pixel| (pixels) for a lens and grid size, computed once.
std::pair<double, double> interpolation_error(int which, int vertices) {
  static std::map<std::pair<int, int>, std::pair<double, double>> cache;
  const auto key = std::pair{which, vertices};
  if (const auto found = cache.find(key); found != cache.end()) return found->second;
  const SpectacleLens lens(bench_lens(which));
  const SourceMap traced = traced_source_map(lens, kFrame, kFraunhoferD_nm);
  const SourceMap grid = grid_source_map(lens, kFrame, kFraunhoferD_nm, vertices);
  double largest = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < traced.position_px.size(); ++i) {
    const glm::dvec2 d = grid.position_px[i] - traced.position_px[i];
    const double error = std::sqrt(d.x * d.x + d.y * d.y);
    largest = std::max(largest, error);
    sum += error;
  }
  return cache[key] = {largest, sum / static_cast<double>(traced.position_px.size())};
}

void BM_SpectacleGridTrace(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0)), vertices = static_cast<int>(state.range(1));
  const SpectacleLens lens(bench_lens(which));
  for (auto _ : state)
    for (double wavelength : {kFraunhoferC_nm, kFraunhoferD_nm, kFraunhoferF_nm})
      benchmark::DoNotOptimize(trace_grid_vertices(lens, kFrame, wavelength, vertices));
  state.SetLabel(lens_label(which));
}
BENCHMARK(BM_SpectacleGridTrace)->Args({0, 33})->Args({1, 33})->Args({2, 33})->Unit(benchmark::kMillisecond);

void BM_SpectacleWarp(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0)), vertices = static_cast<int>(state.range(1));
  const SpectacleLens lens(bench_lens(which));
  SpectacleWarpOptions options;
  options.grid_vertices = vertices;
  for (auto _ : state) benchmark::DoNotOptimize(warp_through_spectacles(scene(), lens, kFrame, options));
  const auto [largest, mean] = interpolation_error(which, vertices);
  state.counters["max_interp_error_px"] = largest;
  state.counters["mean_interp_error_px"] = mean;
  state.SetLabel(lens_label(which));
}
BENCHMARK(BM_SpectacleWarp)
    ->Args({0, 17})
    ->Args({0, 33})
    ->Args({1, 33})
    ->Args({2, 17})
    ->Args({2, 33})
    ->Unit(benchmark::kMillisecond);

// What sessions run: the warp on one thread per hardware thread, beside its floor, streaming the
// frame's bytes in and out once with the same threads (core/streaming_floor.h).
void BM_SpectacleWarpThreaded(benchmark::State& state) {
  const SpectacleLens lens(bench_lens(0));
  SpectacleWarpOptions options;
  options.threads = static_cast<int>(resolved_threads(0));
  for (auto _ : state) benchmark::DoNotOptimize(warp_through_spectacles(scene(), lens, kFrame, options));
  state.SetLabel(lens_label(0));
}
BENCHMARK(BM_SpectacleWarpThreaded)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SpectacleStreamingFloor(benchmark::State& state) {
  const std::size_t frame_bytes = 16 * static_cast<std::size_t>(kWidth) * kHeight;
  StreamingFloor floor(frame_bytes, frame_bytes, static_cast<int>(resolved_threads(0)));
  for (auto _ : state) floor.run_s();
}
BENCHMARK(BM_SpectacleStreamingFloor)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace glarelab
