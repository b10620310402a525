// CPU glare path: rasterise + FFT + |.|^2 + normalise (the monochromatic PSF) per grid size, in
// double (reference) and float; and the FFT alone.
#include <benchmark/benchmark.h>

#include "glare/cpu/psf.h"

namespace glarelab {
namespace {

ApertureGeometry bench_geometry() {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 6.0;
  geometry.discs.push_back({0.8, -0.5, 0.3, 0.2});
  geometry.defocus_dioptres = 0.5;
  return geometry;
}

void psf_cpu(benchmark::State& state, FftPrecision precision) {
  MonochromaticPsfOptions options;
  options.raster.grid_px = static_cast<int>(state.range(0));
  options.raster.aperture_width_mm = 12.0;
  options.precision = precision;
  const ApertureGeometry geometry = bench_geometry();
  const ApertureGrid grid = rasterise_aperture(geometry, options.raster);
  for (auto _ : state) {
    auto result = compute_monochromatic_psf(grid, geometry.pupil_diameter_mm, geometry.defocus_dioptres, options);
    benchmark::DoNotOptimize(result.psf.values.data());
  }
}

void fft_only(benchmark::State& state, FftPrecision precision) {
  const int n = static_cast<int>(state.range(0));
  const std::size_t count = static_cast<std::size_t>(n) * n;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<std::complex<double>> d(count, {1.0, 0.0});
    std::vector<std::complex<float>> f(count, {1.0f, 0.0f});
    state.ResumeTiming();
    if (precision == FftPrecision::float64) {
      fft2d_forward(d, n, n);
      benchmark::DoNotOptimize(d.data());
    } else {
      fft2d_forward(f, n, n);
      benchmark::DoNotOptimize(f.data());
    }
  }
}

void raster(benchmark::State& state) {
  ApertureRasterOptions options;
  options.grid_px = static_cast<int>(state.range(0));
  options.aperture_width_mm = 12.0;
  const ApertureGeometry geometry = bench_geometry();
  for (auto _ : state) benchmark::DoNotOptimize(rasterise_aperture(geometry, options).transmittance.data());
}

BENCHMARK_CAPTURE(psf_cpu, double, FftPrecision::float64)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(psf_cpu, float, FftPrecision::float32)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fft_only, double, FftPrecision::float64)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(fft_only, float, FftPrecision::float32)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);
BENCHMARK(raster)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace glarelab
