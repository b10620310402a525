// The depth-of-field stage (stimuli/depth_of_field.h) on a 1024 x 768 frame with a depth map, on
// 2 threads (and 1 for comparison), with the layers it needed and its error against the per-pixel reference
// (stimuli/depth_of_field_reference.h) beside the time.
//
// The scene: a far wall at 4 m over the upper half, a floor running from 4 m at the horizon to
// 0.45 m at the bottom row, and three boards in front (0.4 m, 0.6 m, 1.5 m). The eye: accommodated
// at 0.6 m with -0.5 D of cylinder at TABO 20, pupil radius 2 mm; the display 1024 x 768 px at
// 0.25 mm pitch seen from 600 mm (0.0239 deg a pixel: 4.8 px of blur per dioptre of error).
//
// For scale, Kakimoto et al. 2007 (section 5; GeForce 7800 GTX, 3.2 GHz Pentium 4, 1024 x 768):
// the blurred image of their Figure 1 (left, ten-sample blur, no spectacle lens) at about 30 fps
// (33 ms a frame), 20.1 fps with the lens' refraction. Their blur draws the scene's geometry ten
// times with displaced vertices; this stage blurs an image with depth on the CPU.
//
// BM_DepthLayerBlur* time one layer's blur both ways (direct, FFT) for the kernel sizes the stage
// meets, full-frame and as a 32-row band (a slice of the floor): the crossover behind
// cheaper_layer_convolution (stimuli/depth_of_field_blur.cpp).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <ctime>
#include <vector>

#include "core/display_spec.h"
#include "stimuli/depth_of_field.h"
#include "stimuli/depth_of_field_benchmark.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/depth_of_field_reference.h"
#include "stimuli/display_model.h"

namespace glarelab {
namespace {

constexpr int kWidth = 1024;
constexpr int kHeight = 768;
constexpr int kThreads = 2;

using BenchScene = DepthBenchScene;
const BenchScene& bench_scene() { return depth_of_field_bench_scene(); }
DepthOfFieldSettings bench_settings(int threads) { return depth_of_field_bench_settings(threads); }

// The per-pixel reference of the bench scene, computed once (it does not depend on threads).
const ImageRGBA& bench_reference() {
  static const ImageRGBA reference =
      depth_of_field_reference(bench_scene().image, bench_scene().depth_m, bench_settings(1));
  return reference;
}

// Pixels within kEdgeRadiusPx of a depth edge (a vergence change of more than 0.2 D inside the
// square window), where the layered stage and the reference differ by design (occlusion); the rest
// is smooth depth, where only the blur quantisation of the layers remains.
constexpr int kEdgeRadiusPx = 12;
const std::vector<bool>& near_depth_edge() {
  static const std::vector<bool> mask = [] {
    const std::vector<float>& depth = bench_scene().depth_m;
    std::vector<float> low(depth.size()), high(depth.size());
    for (std::size_t k = 0; k < depth.size(); ++k) low[k] = high[k] = 1.0f / depth[k];
    // Separable running min and max over the window: rows, then columns.
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<float> low_in = low, high_in = high;
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          float lo = INFINITY, hi = -INFINITY;
          for (int d = -kEdgeRadiusPx; d <= kEdgeRadiusPx; ++d) {
            const int sx = pass == 0 ? x + d : x, sy = pass == 0 ? y : y + d;
            if (sx < 0 || sy < 0 || sx >= kWidth || sy >= kHeight) continue;
            const std::size_t k = static_cast<std::size_t>(sy) * kWidth + sx;
            lo = std::min(lo, low_in[k]);
            hi = std::max(hi, high_in[k]);
          }
          low[static_cast<std::size_t>(y) * kWidth + x] = lo;
          high[static_cast<std::size_t>(y) * kWidth + x] = hi;
        }
    }
    std::vector<bool> edge(depth.size());
    for (std::size_t k = 0; k < depth.size(); ++k) edge[k] = high[k] - low[k] > 0.2f;
    return edge;
  }();
  return mask;
}

// Mean |result - reference| over R, G, B of the pixels on (or off) depth edges, relative to the
// reference's mean there.
double mean_relative_error(const ImageRGBA& result, const ImageRGBA& reference, bool on_edges) {
  double difference = 0.0, total = 0.0;
  for (std::size_t k = 0; k < near_depth_edge().size(); ++k) {
    if (near_depth_edge()[k] != on_edges) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      difference += std::abs(static_cast<double>(result.rgba[4 * k + c]) - reference.rgba[4 * k + c]);
      total += reference.rgba[4 * k + c];
    }
  }
  return total > 0.0 ? difference / total : 0.0;
}

// state.range(0) threads: 2 is the lab machines' count (the figure in docs/DEPTH_OF_FIELD.md); 1
// shows what the threads bring. state.range(1): the layer tolerance in hundredths of a pixel (25,
// the default; smaller ones trade time for error).
void BM_DepthOfField1024x768(benchmark::State& state) {
  const BenchScene& scene = bench_scene();
  const int threads = static_cast<int>(state.range(0));
  DepthOfFieldSettings settings = bench_settings(threads);
  settings.tolerance_px = static_cast<double>(state.range(1)) / 100.0;
  DepthOfFieldReport report;
  ImageRGBA result;
  // CPU time of the whole process (every thread) a frame: on a machine shared with other work the
  // wall-clock time says more about the load than about the stage.
  const std::clock_t cpu_start = std::clock();
  for (auto _ : state) {
    result = apply_depth_of_field(scene.image, scene.depth_m, settings, &report);
    benchmark::DoNotOptimize(result.rgba.data());
  }
  state.counters["cpu_all_threads_ms"] =
      1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC / static_cast<double>(state.iterations());
  const DepthOfFieldError error = depth_of_field_error(result, bench_reference());
  state.counters["threads"] = threads;
  state.counters["layers"] = report.layers;
  state.counters["blurred"] = report.blurred_layers;
  state.counters["direct"] = report.direct_layers;
  state.counters["fft"] = report.fft_layers;
  state.counters["blur_err_px"] = report.max_blur_error_px;
  state.counters["ref_mean_rel"] = error.mean_relative;
  state.counters["ref_mean_cd_m2"] = error.mean_abs_cd_m2;
  state.counters["ref_max_cd_m2"] = error.max_abs_cd_m2;
  state.counters["ref_rel_smooth"] = mean_relative_error(result, bench_reference(), false);
  state.counters["ref_rel_edges"] = mean_relative_error(result, bench_reference(), true);
}
BENCHMARK(BM_DepthOfField1024x768)
    ->Args({kThreads, 25})
    ->Args({1, 25})
    ->Args({kThreads, 10})
    ->Args({kThreads, 5})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

// The worst case for the layer rule's bookkeeping: a plane tilted in x and y, so that every pixel
// has its own depth (vergence 0.2 to 2.2 D, one float step apart or more) and every layer is a
// diagonal band across the frame. No reference here: the bench scene above measures the error.
void BM_DepthOfFieldTiltedPlane1024x768(benchmark::State& state) {
  static const std::vector<float> depth = [] {
    std::vector<float> d(static_cast<std::size_t>(kWidth) * kHeight);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        d[static_cast<std::size_t>(y) * kWidth + x] =
            static_cast<float>(1.0 / (0.2 + 2.0 * (0.6 * x / (kWidth - 1) + 0.4 * y / (kHeight - 1))));
    return d;
  }();
  DepthOfFieldSettings settings = bench_settings(kThreads);
  settings.tolerance_px = static_cast<double>(state.range(0)) / 100.0;  // hundredths of a pixel
  DepthOfFieldReport report;
  const std::clock_t cpu_start = std::clock();
  for (auto _ : state)
    benchmark::DoNotOptimize(apply_depth_of_field(bench_scene().image, depth, settings, &report).rgba.data());
  state.counters["cpu_all_threads_ms"] =
      1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC / static_cast<double>(state.iterations());
  state.counters["layers"] = report.layers;
  state.counters["direct"] = report.direct_layers;
  state.counters["fft"] = report.fft_layers;
  state.counters["blur_err_px"] = report.max_blur_error_px;
}
BENCHMARK(BM_DepthOfFieldTiltedPlane1024x768)->Arg(25)->Arg(10)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

// One layer of `rows` x 1024 px blurred by a circle of radius state.range(0) px, one way.
void layer_blur(benchmark::State& state, LayerConvolution method, int rows) {
  LayerImage layer;
  layer.width_px = kWidth;
  layer.height_px = rows;
  layer.rgba.assign(4 * static_cast<std::size_t>(kWidth) * rows, 0.0f);
  for (std::size_t k = 0; k < layer.rgba.size(); ++k) layer.rgba[k] = static_cast<float>(k % 97);
  const auto radius = static_cast<double>(state.range(0));
  const EllipticalKernel kernel = elliptical_kernel(PixelBlurEllipse{radius, radius, 0.0});
  for (auto _ : state) benchmark::DoNotOptimize(blur_layer(layer, kernel, method, kThreads).rgba.data());
  state.counters["taps"] = kernel.nonzero_taps();
  state.counters["picks_fft"] = cheaper_layer_convolution(layer, kernel) == LayerConvolution::fft ? 1 : 0;
}

// The kernel sizes of the layer-blur rows, and their units.
void layer_blur_args(benchmark::internal::Benchmark* rows) {
  for (int arg : {1, 2, 4, 8, 10, 12, 16}) rows->Arg(arg);
  rows->Unit(benchmark::kMillisecond)->UseRealTime();
}

void BM_DepthLayerBlurDirectFrame(benchmark::State& state) { layer_blur(state, LayerConvolution::direct, kHeight); }
void BM_DepthLayerBlurFftFrame(benchmark::State& state) { layer_blur(state, LayerConvolution::fft, kHeight); }
void BM_DepthLayerBlurDirectBand(benchmark::State& state) { layer_blur(state, LayerConvolution::direct, 32); }
void BM_DepthLayerBlurFftBand(benchmark::State& state) { layer_blur(state, LayerConvolution::fft, 32); }
BENCHMARK(BM_DepthLayerBlurDirectFrame)->Apply(layer_blur_args);
BENCHMARK(BM_DepthLayerBlurFftFrame)->Apply(layer_blur_args);
BENCHMARK(BM_DepthLayerBlurDirectBand)->Apply(layer_blur_args);
BENCHMARK(BM_DepthLayerBlurFftBand)->Apply(layer_blur_args);

}  // namespace
}  // namespace glarelab
