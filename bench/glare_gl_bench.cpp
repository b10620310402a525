// Speed of the GL glare stages (FFT, PSF, spectral PSF, convolution, the pupil function with and
// without the astigmatic cross term) at 256/512/1024, each with its
// error against FFTW in double as a counter (relative L2), so speed is read beside accuracy.
// The spectral PSF with longitudinal chromatic aberration (one FFT per wavelength) on GL and on the
// float32 CPU path beside the scaled-reference one, at 8, 16 and 32 wavelengths, with its error
// against the float64 reference and the error of fewer wavelengths against 32
// (docs/GLARE_OPTICS.md, "Longitudinal chromatic aberration on the fast paths").
// Times include glFinish: the work is done, not only queued. On llvmpipe (software) the figures
// are CPU figures; `glarelab bench` prints the user-facing table across backends.
#include <benchmark/benchmark.h>
#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "glare/wave/chromatic_psf.h"
#include "glare/wave/cie_cmf.h"
#include "glare/cpu/float_glare.h"
#include "runner/display/compute_context.h"
#include "glare/gl/convolution.h"
#include "glare/gl/fft.h"
#include "glare/gl/psf.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "core/random.h"

namespace glarelab {
namespace {

using Complex = std::complex<double>;

DisplayBackend& context() {
  static const std::unique_ptr<DisplayBackend> backend = gl::create_compute_context();
  return *backend;
}

void fftw_in_place(std::vector<Complex>& data, int width, int height, int sign) {
  fftw_plan plan = fftw_plan_dft_2d(height, width, reinterpret_cast<fftw_complex*>(data.data()),
                                    reinterpret_cast<fftw_complex*>(data.data()), sign, FFTW_ESTIMATE);
  fftw_execute(plan);
  fftw_destroy_plan(plan);
}

template <typename Actual>
double relative_l2(const Actual& actual, const std::vector<double>& expected) {
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    error += (double(actual[i]) - expected[i]) * (double(actual[i]) - expected[i]);
    norm += expected[i] * expected[i];
  }
  return std::sqrt(error / norm);
}

// A pupil with lens-like particles and fibres: enough structure for a realistic spectrum.
ApertureGeometry bench_geometry() {
  const CounterRandom random(1, RandomStream::glare_gl_test_input);
  ApertureGeometry g;
  g.pupil_diameter_mm = 6.0;
  for (std::uint64_t i = 0; i < 200; ++i)
    g.discs.push_back({6.0 * random.uniform(i, 0) - 3.0, 6.0 * random.uniform(i, 1) - 3.0, 0.02 + 0.05 * random.uniform(i, 2), 0.3});
  for (int i = 0; i < 50; ++i) {
    const double angle = 2.0 * 3.14159265358979 * i / 50.0;
    g.lines.push_back({2.0 * std::cos(angle), 2.0 * std::sin(angle), 3.0 * std::cos(angle), 3.0 * std::sin(angle), 0.01, 0.5});
  }
  return g;
}
constexpr double kApertureWidthMm = 12.0;

std::vector<double> reference_power(const std::vector<float>& aperture, int n) {
  std::vector<Complex> field(aperture.begin(), aperture.end());
  fftw_in_place(field, n, n, FFTW_FORWARD);
  std::vector<double> psf(field.size());
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      sum += psf[static_cast<std::size_t>(j) * n + i] = std::norm(field[static_cast<std::size_t>((j + n / 2) % n) * n + (i + n / 2) % n]);
  for (double& value : psf) value /= sum;
  return psf;
}

// Forward transforms of random input on a width x height grid of `layers` layers, each call ended
// by glFinish; the error is layer 0's against FFTW in double.
void time_gl_fft(benchmark::State& state, int width, int height, int layers, std::uint64_t seed) {
  gl::GlFft fft(width, height, layers);
  const CounterRandom random(seed, RandomStream::glare_gl_test_input);
  std::vector<std::complex<float>> input(fft.element_count());
  for (std::size_t i = 0; i < input.size(); ++i)
    input[i] = {static_cast<float>(random.uniform(i, 0) - 0.5), static_cast<float>(random.uniform(i, 1) - 0.5)};
  fft.upload(input);
  fft.transform(gl::FftDirection::forward);
  const auto output = fft.download();
  const std::size_t layer = static_cast<std::size_t>(width) * height;
  std::vector<Complex> expected(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(layer));
  fftw_in_place(expected, width, height, FFTW_FORWARD);
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < layer; ++i) error += std::norm(Complex(output[i]) - expected[i]), norm += std::norm(expected[i]);
  for (auto _ : state) {
    fft.transform(gl::FftDirection::forward);
    glFinish();
  }
  state.counters["rel_l2_vs_fftw_double"] = std::sqrt(error / norm);
  state.counters["elements"] = static_cast<double>(fft.element_count());
}

void BM_GlFft(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  time_gl_fft(state, n, n, 1, 2);
}

// The transforms of the convolution of an N x 3N/4 frame with an N/4 px PSF (glare_benchmark.cpp):
// three layers (R, G, B) of a 2N x N padded grid.
void BM_GlFftConvolutionGrid(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  time_gl_fft(state, 2 * n, n, 3, 4);
}

// The aperture alone (2 x 2 supersampling, 250 primitives); its exactness against the CPU rule
// is tested in tests/glare_gl_aperture_test.cpp.
void BM_GlAperture(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  const ApertureGeometry geometry = bench_geometry();
  gl::GlAperture aperture(n, kApertureWidthMm, 2);
  for (auto _ : state) {
    aperture.draw(geometry);
    glFinish();
  }
  state.counters["primitives"] = static_cast<double>(geometry.discs.size() + geometry.lines.size());
}

void BM_GlPsf(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  const ApertureGeometry geometry = bench_geometry();
  gl::GlPsf psf(n, kApertureWidthMm, 2);
  const Psf result = psf.monochromatic(geometry, 575.0);
  gl::GlAperture aperture(n, kApertureWidthMm, 2);
  aperture.draw(geometry);
  const double error = relative_l2(result.values, reference_power(aperture.read(), n));
  for (auto _ : state) {
    psf.run_monochromatic(geometry, 575.0);
    glFinish();
  }
  state.counters["rel_l2_vs_fftw_double"] = error;
}

// The pupil-function pass alone on a drawn aperture (GlPsf::apply_phase): argument 1 = 0 for a
// spherical error (separable, psf_load_aperture.comp), 1 for an oblique cylinder (the cross term,
// psf_load_aperture_astigmatic.comp). The difference is what the cross term costs.
void BM_GlPupilFunction(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  const bool oblique = state.range(1) != 0;
  gl::GlPsf psf(n, kApertureWidthMm, 2);
  psf.load_field(bench_geometry(), 575.0);
  const DioptricPower error =
      oblique ? DioptricPower::from_prescription({0.5, -1.0, 30.0}) : DioptricPower::spherical(0.5);
  for (auto _ : state) {
    psf.apply_phase(error, 575.0);
    glFinish();
  }
}

void BM_GlSpectralPsf(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  const ApertureGeometry geometry = bench_geometry();
  gl::GlPsf psf(n, kApertureWidthMm, 2);
  const Psf result = psf.spectral(geometry, 32, 575.0);
  gl::GlAperture aperture(n, kApertureWidthMm, 2);
  aperture.draw(geometry);
  const std::vector<double> reference = reference_power(aperture.read(), n);
  const std::size_t count = static_cast<std::size_t>(n) * n;
  std::vector<double> expected(3 * count, 0.0);
  const auto at = [&](int i, int j) { return i < 0 || j < 0 || i >= n || j >= n ? 0.0 : reference[static_cast<std::size_t>(j) * n + i]; };
  for (const SpectralSample& sample : spectral_samples(32)) {
    const double k = 575.0 / sample.wavelength_nm;
    const double weight[3] = {sample.weight.r, sample.weight.g, sample.weight.b};
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double sx = n / 2.0 + (x - n / 2.0) * k, sy = n / 2.0 + (y - n / 2.0) * k;
        const int i = static_cast<int>(std::floor(sx)), j = static_cast<int>(std::floor(sy));
        const double fx = sx - i, fy = sy - j;
        const double value = k * k * ((1 - fy) * ((1 - fx) * at(i, j) + fx * at(i + 1, j)) + fy * ((1 - fx) * at(i, j + 1) + fx * at(i + 1, j + 1)));
        for (int c = 0; c < 3; ++c) expected[c * count + static_cast<std::size_t>(y) * n + x] += weight[c] * value;
      }
  }
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) sum += (expected[c * count + i] = std::max(expected[c * count + i], 0.0));
    for (std::size_t i = 0; i < count; ++i) expected[c * count + i] /= sum;
  }
  const double error = relative_l2(result.values, expected);
  for (auto _ : state) {
    psf.run_spectral(geometry, 32, 575.0);
    glFinish();
  }
  state.counters["rel_l2_vs_fftw_double"] = error;
}

// An N x 3N/4 frame (not a power of two) with a few sources over a dim background, convolved
// with a 127 px three-channel PSF; reference: the same zero-padded convolution by FFTW in double.
void BM_GlConvolution(benchmark::State& state) {
  context();
  const int w = static_cast<int>(state.range(0)), h = w * 3 / 4, k = 127;
  const CounterRandom random(3, RandomStream::glare_gl_test_input);
  ImageRGBA image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = static_cast<float>(1.0 + 10.0 * random.uniform(static_cast<std::uint64_t>(y * w + x), static_cast<std::uint32_t>(c)));
  Psf psf{k, 0.01, 3, std::vector<double>(3 * static_cast<std::size_t>(k) * k)};
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) {
        const double r = std::hypot(x - k / 2, y - k / 2);
        sum += psf.at(c, x, y) = std::exp(-r * r / (2.0 + c)) + 1e-3 / (1.0 + r * r * r);
      }
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x) psf.at(c, x, y) /= sum;
  }
  gl::GlConvolution convolution;
  const ImageRGBA result = convolution.convolve(image, psf);
  const int pw = gl::padded_fft_length(w + k - 1), ph = gl::padded_fft_length(h + k - 1);
  const std::size_t layer = static_cast<std::size_t>(pw) * ph;
  std::vector<double> expected, actual;
  for (int c = 0; c < 3; ++c) {
    std::vector<Complex> a(layer), b(layer);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) a[static_cast<std::size_t>(y) * pw + x] = image.pixel(x, y)[c];
    for (int v = 0; v < k; ++v)
      for (int u = 0; u < k; ++u) b[static_cast<std::size_t>((v - k / 2 + ph) % ph) * pw + (u - k / 2 + pw) % pw] = psf.at(c, u, v);
    fftw_in_place(a, pw, ph, FFTW_FORWARD);
    fftw_in_place(b, pw, ph, FFTW_FORWARD);
    for (std::size_t i = 0; i < layer; ++i) a[i] *= b[i] / static_cast<double>(layer);
    fftw_in_place(a, pw, ph, FFTW_BACKWARD);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        expected.push_back(a[static_cast<std::size_t>(y) * pw + x].real());
        actual.push_back(result.pixel(x, y)[c]);
      }
  }
  const double error = relative_l2(actual, expected);
  for (auto _ : state) {
    benchmark::DoNotOptimize(convolution.convolve(image, psf));
  }
  state.counters["rel_l2_vs_fftw_double"] = error;
  state.counters["padded_px"] = static_cast<double>(pw) * ph;
}

// A -2 D myope (residual error +2 D at 575 nm) with a 4 mm pupil alone: the GL aperture is the CPU
// rasteriser's pixel for pixel for a bare pupil, so the chromatic PSFs compare with the float64
// reference without an aperture difference. 8 mm across the pupil plane: at N = 512 no wavelength
// aliases (+4.06 D at 380 nm steps 2.1 rad per pixel at the pupil's edge), at N = 256 the blue end
// does (4.2 rad); both paths compute the same sampled function either way.
constexpr double kChromaticWidthMm = 8.0;
ApertureGeometry chromatic_geometry() {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  geometry.refraction_error = DioptricPower::spherical(2.0);
  return geometry;
}

ChromaticPsfResult chromatic_reference(int n, int wavelengths) {
  ChromaticPsfOptions options;
  options.raster.grid_px = n;
  options.raster.aperture_width_mm = kChromaticWidthMm;
  options.wavelength_samples = wavelengths;
  return compute_chromatic_psf(chromatic_geometry(), options);
}

// The largest of the three channels' relative L2 errors.
double worst_channel_l2(const Psf& test, const Psf& expected) {
  const std::size_t plane = static_cast<std::size_t>(expected.size_px) * expected.size_px;
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) {
    double error = 0.0, norm = 0.0;
    for (std::size_t k = c * plane; k < (c + 1) * plane; ++k) {
      error += (test.values[k] - expected.values[k]) * (test.values[k] - expected.values[k]);
      norm += expected.values[k] * expected.values[k];
    }
    worst = std::max(worst, std::sqrt(error / norm));
  }
  return worst;
}

// GL: the scaled-reference spectral PSF (arg 2 = 0, one FFT) or the one with LCA (1, one FFT per
// wavelength); args N, wavelengths. Counter: the LCA PSF's worst channel against compute_chromatic_psf.
void BM_GlChromaticPsf(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0)), wavelengths = static_cast<int>(state.range(1));
  const bool lca = state.range(2) != 0;
  const ApertureGeometry geometry = chromatic_geometry();
  gl::GlPsf psf(n, kChromaticWidthMm, 2);
  // Warm-up (llvmpipe compiles each shader at its first dispatch) and the error.
  if (lca) {
    const Psf result = psf.chromatic(geometry, wavelengths, 575.0);
    state.counters["rel_l2_vs_float64"] = worst_channel_l2(result, chromatic_reference(n, wavelengths).spectral.psf);
  } else {
    psf.run_spectral(geometry, wavelengths, 575.0);
  }
  glFinish();
  for (auto _ : state) {
    if (lca) psf.run_chromatic(geometry, wavelengths, 575.0);
    else psf.run_spectral(geometry, wavelengths, 575.0);
    glFinish();
  }
}

// The float32 CPU path's display PSF (CpuFloatGlare::display_psf: aperture, FFT(s), spectral PSF at
// 4 PSF pixels per display pixel), scaled reference (arg 2 = 0) or LCA (1). Counter: the LCA one's
// worst channel against compute_chromatic_psf resampled the same way.
void BM_CpuPlannedChromaticPsf(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), wavelengths = static_cast<int>(state.range(1));
  CpuFloatGlareSettings settings;
  settings.grid_px = n;
  settings.aperture_width_mm = kChromaticWidthMm;
  settings.wavelength_samples = wavelengths;
  settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(575.0, kChromaticWidthMm);
  settings.longitudinal_chromatic_aberration = state.range(2) != 0;
  CpuFloatGlare glare(settings);
  const ApertureGeometry geometry = chromatic_geometry();
  const Psf first = glare.display_psf(geometry);
  if (settings.longitudinal_chromatic_aberration)
    state.counters["rel_l2_vs_float64"] = worst_channel_l2(
        first, resample_psf_to_display(chromatic_reference(n, wavelengths).spectral.psf, settings.display_degrees_per_pixel));
  for (auto _ : state) benchmark::DoNotOptimize(glare.display_psf(geometry));
}

// The float64 reference (compute_chromatic_psf) itself, args N, wavelengths; counters: each channel's
// relative L2 against the 32-wavelength PSF of the same N (what fewer wavelengths cost).
void BM_CpuDoubleChromaticPsf(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), wavelengths = static_cast<int>(state.range(1));
  const Psf psf = chromatic_reference(n, wavelengths).spectral.psf;
  const Psf full = chromatic_reference(n, 32).spectral.psf;
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  for (int c = 0; c < 3; ++c) {
    double error = 0.0, norm = 0.0;
    for (std::size_t k = c * plane; k < (c + 1) * plane; ++k) {
      error += (psf.values[k] - full.values[k]) * (psf.values[k] - full.values[k]);
      norm += full.values[k] * full.values[k];
    }
    state.counters[std::string("rel_l2_vs_32_") + "RGB"[c]] = std::sqrt(error / norm);
  }
  for (auto _ : state) benchmark::DoNotOptimize(chromatic_reference(n, wavelengths));
}

void chromatic_arguments(benchmark::internal::Benchmark* benchmark) {
  for (int n : {256, 512})
    for (int wavelengths : {8, 16, 32})
      for (int lca : {0, 1}) benchmark->Args({n, wavelengths, lca});
}

BENCHMARK(BM_GlFft)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlFftConvolutionGrid)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlAperture)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlPsf)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlPupilFunction)
    ->Args({512, 0})
    ->Args({512, 1})
    ->Args({1024, 0})
    ->Args({1024, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_GlSpectralPsf)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlConvolution)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GlChromaticPsf)->Apply(chromatic_arguments)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CpuPlannedChromaticPsf)->Apply(chromatic_arguments)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CpuDoubleChromaticPsf)
    ->Args({256, 8})
    ->Args({256, 16})
    ->Args({512, 8})
    ->Args({512, 16})
    ->Args({512, 32})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace glarelab
