// Speed of the GL glare stages (FFT, PSF, spectral PSF, convolution, the pupil function with and
// without the astigmatic cross term) at 256/512/1024, each with its
// error against FFTW in double as a counter (relative L2), so speed is read beside accuracy.
// Times include glFinish: the work is done, not only queued. On llvmpipe (software) the figures
// are CPU figures; `glarelab bench` prints the user-facing table across backends.
#include <benchmark/benchmark.h>
#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <vector>

#include "glare/cie_cmf.h"
#include "runner/display/compute_context.h"
#include "glare/gl/gl_convolution.h"
#include "glare/gl/gl_fft.h"
#include "glare/gl/gl_psf.h"
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

void BM_GlFft(benchmark::State& state) {
  context();
  const int n = static_cast<int>(state.range(0));
  gl::GlFft fft(n, n);
  const CounterRandom random(2, RandomStream::glare_gl_test_input);
  std::vector<std::complex<float>> input(fft.element_count());
  for (std::size_t i = 0; i < input.size(); ++i)
    input[i] = {static_cast<float>(random.uniform(i, 0) - 0.5), static_cast<float>(random.uniform(i, 1) - 0.5)};
  fft.upload(input);
  fft.transform(gl::FftDirection::forward);
  const auto output = fft.download();
  std::vector<Complex> expected(input.begin(), input.end());
  fftw_in_place(expected, n, n, FFTW_FORWARD);
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < expected.size(); ++i) error += std::norm(Complex(output[i]) - expected[i]), norm += std::norm(expected[i]);
  for (auto _ : state) {
    fft.transform(gl::FftDirection::forward);
    glFinish();
  }
  state.counters["rel_l2_vs_fftw_double"] = std::sqrt(error / norm);
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

BENCHMARK(BM_GlFft)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
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

}  // namespace
}  // namespace glarelab
