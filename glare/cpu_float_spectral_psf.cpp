#include "glare/cpu_float_spectral_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "glare/cie_cmf.h"
#include "glare/parallel_rows.h"
#include "glare/psf_scale.h"

namespace glarelab {

namespace {

// rows x [c0, c1) of `source` (rows `source_stride` apart) written transposed: value (r, k) to
// target[k * target_stride + r]. In 4 x 4 blocks of SSE registers where the compiler has them (x86-64
// always does): the compiler made the element-by-element copy one scalar load and store per value,
// 14 % of the spectral stage's time. A copy: the values are the same bits either way.
void transpose_tile(const float* source, int source_stride, int rows, int c0, int c1, float* target, int target_stride) {
  const auto at = [](int index, int stride) { return static_cast<std::size_t>(index) * static_cast<std::size_t>(stride); };
  int k = c0;
#if defined(__SSE__)
  for (; k + 4 <= c1; k += 4) {
    int r = 0;
    for (; r + 4 <= rows; r += 4) {
      __m128 row0 = _mm_loadu_ps(source + at(r, source_stride) + k);
      __m128 row1 = _mm_loadu_ps(source + at(r + 1, source_stride) + k);
      __m128 row2 = _mm_loadu_ps(source + at(r + 2, source_stride) + k);
      __m128 row3 = _mm_loadu_ps(source + at(r + 3, source_stride) + k);
      _MM_TRANSPOSE4_PS(row0, row1, row2, row3);
      _mm_storeu_ps(target + at(k, target_stride) + r, row0);
      _mm_storeu_ps(target + at(k + 1, target_stride) + r, row1);
      _mm_storeu_ps(target + at(k + 2, target_stride) + r, row2);
      _mm_storeu_ps(target + at(k + 3, target_stride) + r, row3);
    }
    for (; r < rows; ++r)
      for (int j = 0; j < 4; ++j) target[at(k + j, target_stride) + r] = source[at(r, source_stride) + k + j];
  }
#endif
  for (; k < c1; ++k)
    for (int r = 0; r < rows; ++r) target[at(k, target_stride) + r] = source[at(r, source_stride) + k];
}

// The D planes (float) of kCount wavelengths added to a channel's sum and its magnitude (double),
// each in the wavelengths' order. The count is a constant so that the loop over the plane is
// vectorised (it was not with a count known only at run time); the same sums, the same bits.
template <int kCount>
void add_wavelengths(const float* __restrict d_t, std::size_t plane, const double* weight, const double* absolute,
                     double* __restrict target, double* __restrict magnitude) {
  for (std::size_t k = 0; k < plane; ++k) {
    double net = target[k], size = magnitude[k];
    for (int s = 0; s < kCount; ++s) {
      const double d = d_t[static_cast<std::size_t>(s) * plane + k];
      net += weight[s] * d;
      size += absolute[s] * d;
    }
    target[k] = net;
    magnitude[k] = size;
  }
}

// out[0, length) = sum over j < count of weights[j] times row j of `sources` (rows `stride` apart),
// added in j's order from 0, as the element-by-element loops did. Cloned for AVX2 where the compiler
// can (the ifunc picks the clone at load time): 8 floats a step instead of SSE's 4 in the spectral
// stage's two hottest loops. AVX2 without FMA: each product is rounded, then added, as on SSE, so
// both clones give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void weighted_row_sum(float* __restrict out, int length, const float* weights, int count,
                      const float* __restrict sources, std::size_t stride) {
  std::fill(out, out + length, 0.0f);
  for (int j = 0; j < count; ++j) {
    const float weight = weights[j];
    const float* source = sources + static_cast<std::size_t>(j) * stride;
    for (int k = 0; k < length; ++k) out[k] += weight * source[k];
  }
}

// The refinement's two loops (spectral_block), cloned for AVX2 as weighted_row_sum is (the same bits).
// Along x: h[i] = weight0[i] source[index0[i]] + weight1[i] source[index1[i]].
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void interpolate_along_row(const float* __restrict source, const int* index0, const int* index1, const float* weight0,
                           const float* weight1, std::size_t width, float* __restrict h) {
  for (std::size_t i = 0; i < width; ++i) h[i] = weight0[i] * source[index0[i]] + weight1[i] * source[index1[i]];
}

// Along y, then into R, G, B: v = wy0 h0[i] + wy1 h1[i] (float, then double), each channel += its
// weight times v.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
__attribute__((target_clones("avx2", "default")))
#endif
void add_interpolated_column(const float* __restrict h0, const float* __restrict h1, float wy0, float wy1,
                             const double* rgb_weight, std::size_t width, double* __restrict red,
                             double* __restrict green, double* __restrict blue) {
  const double r = rgb_weight[0], g = rgb_weight[1], b = rgb_weight[2];
  for (std::size_t i = 0; i < width; ++i) {
    const double v = wy0 * h0[i] + wy1 * h1[i];
    red[i] += r * v;
    green[i] += g * v;
    blue[i] += b * v;
  }
}

}  // namespace

CpuFloatSpectralPsf::CpuFloatSpectralPsf(const CpuFloatSpectralSettings& settings) : settings_(settings) {
  const int n = settings.grid_px;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/cpu_float_spectral_psf: grid size must be even and >= 2");
  if (!(settings.reference_wavelength_nm > 0.0))
    throw std::invalid_argument("glare/cpu_float_spectral_psf: reference wavelength must be > 0");
  check_psf_fits_display(n, settings.psf_degrees_per_pixel, settings.display_degrees_per_pixel);
  display_px_ = display_psf_size_px(n, settings.psf_degrees_per_pixel, settings.display_degrees_per_pixel);
  const int m_px = display_px_;
  box_ = psf_overlap_weights(n, settings.psf_degrees_per_pixel, m_px, settings.display_degrees_per_pixel);
  const auto& box = box_;
  const double centre = n / 2;
  std::vector<double> dense(static_cast<std::size_t>(n), 0.0);
  for (const SpectralSample& sample : spectral_samples(settings.wavelength_samples)) {
    Wavelength wavelength;
    // spectral_psf.cpp: x_i = (x - c) lambda_ref / lambda + c, value times the Jacobian scale^2.
    const double scale = settings.reference_wavelength_nm / sample.wavelength_nm;
    const double jacobian = scale * scale;
    wavelength.rgb_weight[0] = jacobian * sample.weight.r;
    wavelength.rgb_weight[1] = jacobian * sample.weight.g;
    wavelength.rgb_weight[2] = jacobian * sample.weight.b;
    wavelength.scale = scale;
    for (int x = 0; x < n; ++x) {
      const double position = (x - centre) * scale + centre;
      const double floor_position = std::floor(position);
      const int x0 = static_cast<int>(floor_position);
      const double fraction = position - floor_position;
      const bool inside0 = x0 >= 0 && x0 < n, inside1 = x0 + 1 >= 0 && x0 + 1 < n;
      wavelength.index0.push_back(std::clamp(x0, 0, n - 1));
      wavelength.index1.push_back(std::clamp(x0 + 1, 0, n - 1));
      wavelength.weight0.push_back(inside0 ? static_cast<float>(1.0 - fraction) : 0.0f);
      wavelength.weight1.push_back(inside1 ? static_cast<float>(fraction) : 0.0f);
    }
    wavelength.first_column = n;
    for (int m = 0; m < m_px; ++m) {
      // Row m of W = R B: sum over the PSF pixels x in display pixel m of their bilinear weights.
      int first = n, last = -1;
      for (const PsfOverlap& overlap : box[static_cast<std::size_t>(m)]) {
        const double position = (overlap.input - centre) * scale + centre;
        const double floor_position = std::floor(position);
        const int x0 = static_cast<int>(floor_position);
        const double fraction = position - floor_position;
        // Out-of-grid neighbours read 0, as spectral_psf.cpp's bilinear does.
        if (x0 >= 0 && x0 < n) {
          dense[static_cast<std::size_t>(x0)] += overlap.fraction * (1.0 - fraction);
          first = std::min(first, x0);
          last = std::max(last, x0);
        }
        if (x0 + 1 >= 0 && x0 + 1 < n) {
          dense[static_cast<std::size_t>(x0 + 1)] += overlap.fraction * fraction;
          first = std::min(first, x0 + 1);
          last = std::max(last, x0 + 1);
        }
      }
      Band band;
      band.offset = static_cast<int>(weights_.size());
      if (last >= first) {
        band.first = first;
        band.count = last - first + 1;
        for (int k = first; k <= last; ++k) {
          weights_.push_back(static_cast<float>(dense[static_cast<std::size_t>(k)]));
          dense[static_cast<std::size_t>(k)] = 0.0;
        }
        wavelength.first_column = std::min(wavelength.first_column, first);
        wavelength.last_column = std::max(wavelength.last_column, last);
      }
      wavelength.bands.push_back(band);
    }
    wavelengths_.push_back(std::move(wavelength));
  }
  groups_.resize(kGroups);
  for (Group& group : groups_) {
    group.rows_t.assign(static_cast<std::size_t>(n) * m_px, 0.0f);
    group.row.assign(static_cast<std::size_t>(kTransposeTile) * n, 0.0f);
    group.d_t.assign(static_cast<std::size_t>(kFusedWavelengths) * m_px * m_px, 0.0f);
    group.rgb_t.assign(6 * static_cast<std::size_t>(m_px) * m_px, 0.0);
  }
  straddles_.assign(static_cast<std::size_t>(m_px) * m_px, 0);
}

void CpuFloatSpectralPsf::spectral_block(const float* power, const std::vector<PsfOverlap>& xs,
                                         const std::vector<PsfOverlap>& ys, std::vector<double>& rgb) const {
  const int n = settings_.grid_px;
  const std::size_t width = xs.size(), height = ys.size();
  rgb.assign(3 * width * height, 0.0);
  // Bilinear per wavelength as spectral_psf.cpp, separably: each reference row the block reads is
  // interpolated along x once (consecutive PSF rows share their neighbour rows), then along y.
  // Scratch for the block's columns: a display pixel spans at most display/PSF pixel ratio + 2.
  thread_local std::vector<float> scratch;
  thread_local std::vector<int> indices;
  scratch.resize(4 * width);
  indices.resize(2 * width);
  float *h0 = scratch.data(), *h1 = h0 + width, *weight0 = h1 + width, *weight1 = weight0 + width;
  int *index0 = indices.data(), *index1 = index0 + width;
  for (const Wavelength& wavelength : wavelengths_) {
    for (std::size_t i = 0; i < width; ++i) {
      const auto x = static_cast<std::size_t>(xs[i].input);
      index0[i] = wavelength.index0[x];
      index1[i] = wavelength.index1[x];
      weight0[i] = wavelength.weight0[x];
      weight1[i] = wavelength.weight1[x];
    }
    const auto interpolate_row = [&](int row, float* h) {
      interpolate_along_row(power + static_cast<std::size_t>(row) * n, index0, index1, weight0, weight1, width, h);
    };
    int row0 = -1, row1 = -1;  // the reference rows h0 and h1 hold
    for (std::size_t j = 0; j < height; ++j) {
      const auto y = static_cast<std::size_t>(ys[j].input);
      const int next0 = wavelength.index0[y], next1 = wavelength.index1[y];
      if (next0 == row1 && next0 != row0) {  // moved down one row: the lower neighbour becomes the upper
        std::copy(h1, h1 + width, h0);
        row0 = row1;
      }
      if (next0 != row0) {
        interpolate_row(next0, h0);
        row0 = next0;
      }
      if (next1 != row1) {
        interpolate_row(next1, h1);
        row1 = next1;
      }
      const float wy0 = wavelength.weight0[y], wy1 = wavelength.weight1[y];
      // data(): an empty block (width 0) has no element 0 to take the address of.
      double* red = rgb.data() + j * width;
      double* green = red + height * width;
      double* blue = green + height * width;
      add_interpolated_column(h0, h1, wy0, wy1, wavelength.rgb_weight, width, red, green, blue);
    }
  }
}

Psf CpuFloatSpectralPsf::compute(const float* power, double pupil_diameter_mm) {
  if (!(pupil_diameter_mm > 0.0)) throw std::invalid_argument("glare/cpu_float_spectral_psf: pupil diameter must be > 0 mm");
  const int n = settings_.grid_px, m_px = display_px_;
  const std::size_t plane = static_cast<std::size_t>(m_px) * m_px;
  const int wavelength_count = static_cast<int>(wavelengths_.size());
  const auto run_group = [&](int group_index) {
    Group& group = groups_[static_cast<std::size_t>(group_index)];
    std::fill(group.rgb_t.begin(), group.rgb_t.end(), 0.0);
    const int first_wavelength = wavelength_count * group_index / kGroups;
    const int last_wavelength = wavelength_count * (group_index + 1) / kGroups;
    // The D of up to kFusedWavelengths wavelengths, then added to R, G, B and their magnitudes in
    // one pass (each sum in the wavelengths' order, as one pass per wavelength would add them), so
    // the six double planes are read and written once per kFusedWavelengths wavelengths.
    static_assert(kFusedWavelengths == 4, "add_pending's switch takes 1 to 4 wavelengths");
    std::vector<const Wavelength*> pending;
    const auto add_pending = [&] {
      const std::size_t count = pending.size();
      for (int c = 0; c < 3; ++c) {
        double* target = &group.rgb_t[c * plane];
        double* magnitude = &group.rgb_t[(3 + c) * plane];
        double weight[kFusedWavelengths], absolute[kFusedWavelengths];
        for (std::size_t s = 0; s < count; ++s)
          weight[s] = pending[s]->rgb_weight[c], absolute[s] = std::abs(weight[s]);
        switch (count) {
          case 1: add_wavelengths<1>(group.d_t.data(), plane, weight, absolute, target, magnitude); break;
          case 2: add_wavelengths<2>(group.d_t.data(), plane, weight, absolute, target, magnitude); break;
          case 3: add_wavelengths<3>(group.d_t.data(), plane, weight, absolute, target, magnitude); break;
          default: add_wavelengths<4>(group.d_t.data(), plane, weight, absolute, target, magnitude); break;
        }
      }
      pending.clear();
    };
    for (int w = first_wavelength; w < last_wavelength; ++w) {
      const Wavelength& wavelength = wavelengths_[static_cast<std::size_t>(w)];
      if (wavelength.last_column < wavelength.first_column) continue;
      float* const d_t = &group.d_t[pending.size() * plane];
      const int c0 = wavelength.first_column, c1 = wavelength.last_column + 1;
      // Rows: (W F)(m, :) = sum_j W(m, first + j) F(first + j, :), stored transposed.
      for (int m0 = 0; m0 < m_px; m0 += kTransposeTile) {
        const int tile_rows = std::min(kTransposeTile, m_px - m0);
        for (int r = 0; r < tile_rows; ++r) {
          const Band& band = wavelength.bands[static_cast<std::size_t>(m0 + r)];
          float* row = group.row.data() + static_cast<std::size_t>(r) * n;
          weighted_row_sum(row + c0, c1 - c0, &weights_[static_cast<std::size_t>(band.offset)], band.count,
                           power + static_cast<std::size_t>(band.first) * n + c0, static_cast<std::size_t>(n));
        }
        transpose_tile(group.row.data(), n, tile_rows, c0, c1, &group.rows_t[static_cast<std::size_t>(m0)], m_px);
      }
      // Columns: D^T(m', :) = sum_j W(m', first + j) (W F)^T(first + j, :).
      for (int mx = 0; mx < m_px; ++mx) {
        const Band& band = wavelength.bands[static_cast<std::size_t>(mx)];
        weighted_row_sum(d_t + static_cast<std::size_t>(mx) * m_px, m_px, &weights_[static_cast<std::size_t>(band.offset)],
                         band.count, &group.rows_t[static_cast<std::size_t>(band.first) * m_px], static_cast<std::size_t>(m_px));
      }
      pending.push_back(&wavelength);
      if (pending.size() == static_cast<std::size_t>(kFusedWavelengths)) add_pending();
    }
    if (!pending.empty()) add_pending();
  };
  parallel_chunks(kGroups, settings_.threads, [&](int first, int last) {
    for (int g = first; g < last; ++g) run_group(g);
  });

  // Sum the groups in a fixed order: rgb_t of group 0 holds the totals (R, G, B, magnitudes).
  std::vector<double>& total = groups_.front().rgb_t;
  for (std::size_t g = 1; g < groups_.size(); ++g)
    for (std::size_t k = 0; k < total.size(); ++k) total[k] += groups_[g].rgb_t[k];

  // The clamp. spectral_psf.cpp clamps negative R, G, B on PSF pixels, before the box resampling;
  // clamping the box means instead differs wherever a display pixel's PSF pixels do not all have
  // the same sign (1e-5 of the frame on the eye model's PSFs). Where a channel's sign can change
  // inside a display pixel, the pixel is computed as the double path does, from the PSF pixels it
  // covers, clamped one by one: where its display value is a small part of the magnitude of its
  // wavelengths' contributions, |R| < kStraddle sum_i |w_i| F_i; where a neighbouring display pixel
  // has the other sign (the zero runs close by); and in the core (below). This is a screen, not a
  // bound: elsewhere the sign is taken to be the same all over the pixel and the box mean is
  // clamped; tests/glare_cpu_float_test.cpp and `glarelab bench` check the result against the
  // double path on the eye model's apertures.
  // Spectral PSF error against the float64 path with these (eye model at 1.2 s, 32 wavelengths):
  // 4e-8, 4e-7, 2e-7 at N = 256, 512, 1024, refining 29 %, 14 %, 10 % of the display pixels.
  // Without the neighbour test kStraddle = 0.5 was needed for 1e-7 (and refined twice as many);
  // without the core disk the error was 4e-5 (the red channel's ring at 9.5 PSF pixels).
  constexpr double kStraddle = 0.3, kCoreRings = 8.0;
  // Around the core the rings of each wavelength sit at radii proportional to it (1.22, 2.23, ...
  // lambda / D, Born and Wolf 8.5.2), so a channel changes sign from one PSF pixel to the next
  // there while the box mean stays large: the display pixels within kCoreRings lambda_max / D of the
  // centre are always refined.
  const double longest_nm = spectral_samples(settings_.wavelength_samples).back().wavelength_nm;
  const double core_radius_display_px = kCoreRings * (longest_nm / settings_.reference_wavelength_nm) *
                                        (settings_.aperture_width_mm / pupil_diameter_mm) *
                                        settings_.psf_degrees_per_pixel / settings_.display_degrees_per_pixel;
  // The screen reads `total` and writes only straddles_: its display columns are shared among the
  // threads.
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    for (int mx = first; mx < last; ++mx)
      for (int my = 0; my < m_px; ++my) {
        const std::size_t k = static_cast<std::size_t>(mx) * m_px + my;
        const double dx = static_cast<double>(mx) - m_px / 2, dy = static_cast<double>(my) - m_px / 2;
        bool straddles = dx * dx + dy * dy <= core_radius_display_px * core_radius_display_px;
        for (int c = 0; c < 3 && !straddles; ++c) {
          const double net = total[c * plane + k], magnitude = total[(3 + c) * plane + k];
          if (magnitude > 0.0 && std::abs(net) < kStraddle * magnitude) straddles = true;
          // A neighbour of the other sign: the channel's zero runs close by.
          for (int ny = std::max(0, my - 1); ny <= std::min(m_px - 1, my + 1) && !straddles; ++ny)
            for (int nx = std::max(0, mx - 1); nx <= std::min(m_px - 1, mx + 1); ++nx)
              if ((total[c * plane + static_cast<std::size_t>(nx) * m_px + ny] < 0.0) != (net < 0.0)) straddles = true;
        }
        straddles_[k] = straddles ? 1 : 0;
      }
  });
  refined_pixels_ = 0;
  for (const unsigned char straddles : straddles_) refined_pixels_ += straddles;
  // rgb_t is transposed: index x * M + y. Display rows on the threads; along a row, each run of
  // refined display pixels has its PSF pixels computed in one block (the PSF columns from the run's
  // first to its last, each once, in rows the loops over them vectorise along), then each display
  // pixel sums its own PSF pixels clamped, in the order one block per pixel would: the same sums.
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    std::vector<double> block;
    std::vector<PsfOverlap> columns;
    for (int my = first; my < last; ++my) {
      const auto& ys = box_[static_cast<std::size_t>(my)];
      const auto refined = [&](int mx) { return straddles_[static_cast<std::size_t>(mx) * m_px + my] != 0; };
      for (int run_start = 0; run_start < m_px;) {
        if (!refined(run_start)) {
          ++run_start;
          continue;
        }
        int run_end = run_start;
        int lowest = n, highest = -1;
        for (; run_end < m_px && refined(run_end); ++run_end)
          for (const PsfOverlap& overlap : box_[static_cast<std::size_t>(run_end)])
            lowest = std::min(lowest, overlap.input), highest = std::max(highest, overlap.input);
        columns.clear();
        for (int column = lowest; column <= highest; ++column) columns.push_back({column, 1.0});
        spectral_block(power, columns, ys, block);
        const std::size_t width = columns.size(), rows = ys.size();
        for (int mx = run_start; mx < run_end; ++mx) {
          const auto& xs = box_[static_cast<std::size_t>(mx)];
          double sum[3] = {0.0, 0.0, 0.0};
          for (std::size_t j = 0; j < rows; ++j)
            for (const PsfOverlap& x : xs) {
              const double area = x.fraction * ys[j].fraction;
              const std::size_t at = j * width + static_cast<std::size_t>(x.input - lowest);
              for (std::size_t c = 0; c < 3; ++c) sum[c] += area * std::max(0.0, block[c * rows * width + at]);
            }
          for (int c = 0; c < 3; ++c) total[c * plane + static_cast<std::size_t>(mx) * m_px + my] = sum[c];
        }
        run_start = run_end;
      }
    }
  });

  Psf psf;
  psf.size_px = m_px;
  psf.channels = 3;
  psf.degrees_per_pixel = settings_.display_degrees_per_pixel;
  psf.values.assign(3 * plane, 0.0);
  for (int c = 0; c < 3; ++c) {
    double positive = 0.0;
    for (int x = 0; x < m_px; ++x)
      for (int y = 0; y < m_px; ++y) {
        const double value = std::max(0.0, total[c * plane + static_cast<std::size_t>(x) * m_px + y]);
        positive += value;
        psf.at(c, x, y) = value;
      }
    if (!(positive > 0.0)) throw std::runtime_error("glare/cpu_float_spectral_psf: a Rec.709 channel has no positive energy");
    const double inverse = 1.0 / positive;
    for (std::size_t k = 0; k < plane; ++k) psf.values[c * plane + k] *= inverse;
  }
  return psf;
}

}  // namespace glarelab
