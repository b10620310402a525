// The planned float32 CPU glare path (glare/cpu_float_*.h) stage by stage, and the FFTW floor it is
// measured against (glare/cpu/fftw_floor.h), per grid size N on the eye model's aperture (default
// parameters, seed 1) with an N x 3N/4 frame and the PSF at N/4 display pixels, as `glarelab bench`.
// Each iteration of the stages that depend on the eye takes it at a new time (1/60 s later, blinks
// skipped), as in dynamic glare.
#include <benchmark/benchmark.h>

#include <vector>

#include "glare/cpu/float_convolution.h"
#include "glare/cpu/float_psf.h"
#include "glare/cpu/float_spectral_psf.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/fftw_floor.h"

namespace glarelab {
namespace {

constexpr double kWidthMm = 10.0;

// 64 eye geometries 1/60 s apart, cycled through by the iterations.
const std::vector<ApertureGeometry>& eye_geometries() {
  static const std::vector<ApertureGeometry> geometries = [] {
    const EyeModel eye(EyeParameters{}, 1);
    std::vector<ApertureGeometry> list;
    for (double t = 1.2; list.size() < 64; t += 1.0 / 60.0)
      if (eye.state_at(t).blink_closure == 0.0) list.push_back(eye.geometry_at(t));
    return list;
  }();
  return geometries;
}

struct Planned {
  CpuFloatPsf psf;
  CpuFloatSpectralPsf spectral;
  CpuFloatConvolution convolution;
  ImageRGBA scene;
  explicit Planned(int n)
      : psf(psf_settings(n)), spectral(spectral_settings(n, psf.degrees_per_pixel())),
        convolution(n, n * 3 / 4, spectral.display_size_px()), scene(n, n * 3 / 4, 1.0f) {
    scene.pixel(n / 2, n / 4)[0] = 1e5f;
  }
  static CpuFloatPsfSettings psf_settings(int n) {
    CpuFloatPsfSettings settings;
    settings.raster.grid_px = n;
    settings.raster.aperture_width_mm = kWidthMm;
    return settings;
  }
  static CpuFloatSpectralSettings spectral_settings(int n, double psf_degrees_per_pixel) {
    CpuFloatSpectralSettings settings;
    settings.grid_px = n;
    settings.psf_degrees_per_pixel = psf_degrees_per_pixel;
    settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel;
    settings.aperture_width_mm = kWidthMm;
    settings.threads = kGlareCpuThreads;
    return settings;
  }
  Psf kernel_for(const ApertureGeometry& geometry) {
    psf.rasterise(geometry);
    psf.transform(geometry.pupil_diameter_mm, geometry.defocus_dioptres);
    return spectral.compute(psf.power_column_major(), geometry.pupil_diameter_mm);
  }
};

void float_aperture(benchmark::State& state) {
  Planned planned(static_cast<int>(state.range(0)));
  std::size_t k = 0;
  for (auto _ : state) planned.psf.rasterise(eye_geometries()[k++ % eye_geometries().size()]);
}

void float_psf(benchmark::State& state) {  // phase, N x N FFT, shifted power; the aperture outside the timing
  Planned planned(static_cast<int>(state.range(0)));
  std::size_t k = 0;
  for (auto _ : state) {
    const ApertureGeometry& geometry = eye_geometries()[k++ % eye_geometries().size()];
    state.PauseTiming();
    planned.psf.rasterise(geometry);
    state.ResumeTiming();
    planned.psf.transform(geometry.pupil_diameter_mm, geometry.defocus_dioptres);
  }
}

void float_spectral(benchmark::State& state) {  // 32 wavelengths at the display scale
  Planned planned(static_cast<int>(state.range(0)));
  std::size_t k = 0;
  for (auto _ : state) {
    const ApertureGeometry& geometry = eye_geometries()[k++ % eye_geometries().size()];
    state.PauseTiming();
    planned.psf.rasterise(geometry);
    planned.psf.transform(geometry.pupil_diameter_mm, geometry.defocus_dioptres);
    state.ResumeTiming();
    benchmark::DoNotOptimize(planned.spectral.compute(planned.psf.power_column_major(), geometry.pupil_diameter_mm).values.data());
  }
}

void float_convolution(benchmark::State& state, bool new_scene) {  // a new PSF every frame
  Planned planned(static_cast<int>(state.range(0)));
  const Psf kernel = planned.kernel_for(eye_geometries().front());
  planned.convolution.set_scene(planned.scene);
  ImageRGBA out;
  for (auto _ : state) {
    if (new_scene) planned.convolution.set_scene(planned.scene);
    planned.convolution.convolve(kernel, out);
  }
}

void float_frame(benchmark::State& state, bool new_scene) {  // the whole dynamic frame
  Planned planned(static_cast<int>(state.range(0)));
  planned.convolution.set_scene(planned.scene);
  ImageRGBA out;
  std::size_t k = 0;
  for (auto _ : state) {
    const Psf kernel = planned.kernel_for(eye_geometries()[k++ % eye_geometries().size()]);
    if (new_scene) planned.convolution.set_scene(planned.scene);
    planned.convolution.convolve(kernel, out);
  }
}

void fftw_floor(benchmark::State& state) {  // 1 N x N complex + 9 padded real transforms
  const int n = static_cast<int>(state.range(0));
  Planned planned(n);
  FftwFloatFloor floor(n, planned.convolution.fft_rows(), planned.convolution.fft_cols());
  for (auto _ : state) floor.run();
}

BENCHMARK(float_aperture)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(float_psf)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(float_spectral)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_convolution, static_scene, false)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_convolution, new_scene, true)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_frame, static_scene, false)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(float_frame, new_scene, true)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(fftw_floor)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace glarelab
