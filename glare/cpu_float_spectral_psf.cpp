#include "glare/cpu_float_spectral_psf.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "glare/cie_cmf.h"
#include "glare/parallel_rows.h"
#include "glare/psf_scale.h"

namespace glarelab {

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
      wavelength.x0.push_back(static_cast<int>(floor_position));
      wavelength.fraction.push_back(static_cast<float>(position - floor_position));
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
    group.row.assign(static_cast<std::size_t>(n), 0.0f);
    group.d_t.assign(static_cast<std::size_t>(m_px) * m_px, 0.0f);
    group.rgb_t.assign(6 * static_cast<std::size_t>(m_px) * m_px, 0.0);
  }
  straddles_.assign(static_cast<std::size_t>(m_px) * m_px, 0);
}

void CpuFloatSpectralPsf::spectral_at(const float* power, int x, int y, double rgb[3]) const {
  const int n = settings_.grid_px;
  rgb[0] = rgb[1] = rgb[2] = 0.0;
  const auto value = [&](int xi, int yi) {
    if (xi < 0 || yi < 0 || xi >= n || yi >= n) return 0.0;
    return static_cast<double>(power[static_cast<std::size_t>(yi) * n + xi]);
  };
  for (const Wavelength& wavelength : wavelengths_) {
    const int x0 = wavelength.x0[static_cast<std::size_t>(x)], y0 = wavelength.x0[static_cast<std::size_t>(y)];
    const double fx = wavelength.fraction[static_cast<std::size_t>(x)], fy = wavelength.fraction[static_cast<std::size_t>(y)];
    const double v = (1 - fy) * ((1 - fx) * value(x0, y0) + fx * value(x0 + 1, y0)) +
                     fy * ((1 - fx) * value(x0, y0 + 1) + fx * value(x0 + 1, y0 + 1));
    for (int c = 0; c < 3; ++c) rgb[c] += wavelength.rgb_weight[c] * v;
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
    for (int w = first_wavelength; w < last_wavelength; ++w) {
      const Wavelength& wavelength = wavelengths_[static_cast<std::size_t>(w)];
      if (wavelength.last_column < wavelength.first_column) continue;
      const int c0 = wavelength.first_column, c1 = wavelength.last_column + 1;
      // Rows: (W F)(m, :) = sum_j W(m, first + j) F(first + j, :), stored transposed.
      for (int m = 0; m < m_px; ++m) {
        const Band& band = wavelength.bands[static_cast<std::size_t>(m)];
        float* row = group.row.data();
        std::fill(row + c0, row + c1, 0.0f);
        for (int j = 0; j < band.count; ++j) {
          const float weight = weights_[static_cast<std::size_t>(band.offset + j)];
          const float* source = power + static_cast<std::size_t>(band.first + j) * n;
          for (int k = c0; k < c1; ++k) row[k] += weight * source[k];
        }
        for (int k = c0; k < c1; ++k) group.rows_t[static_cast<std::size_t>(k) * m_px + m] = row[k];
      }
      // Columns: D^T(m', :) = sum_j W(m', first + j) (W F)^T(first + j, :).
      for (int mx = 0; mx < m_px; ++mx) {
        const Band& band = wavelength.bands[static_cast<std::size_t>(mx)];
        float* d = &group.d_t[static_cast<std::size_t>(mx) * m_px];
        std::fill(d, d + m_px, 0.0f);
        for (int j = 0; j < band.count; ++j) {
          const float weight = weights_[static_cast<std::size_t>(band.offset + j)];
          const float* source = &group.rows_t[static_cast<std::size_t>(band.first + j) * m_px];
          for (int my = 0; my < m_px; ++my) d[my] += weight * source[my];
        }
      }
      for (int c = 0; c < 3; ++c) {
        double* target = &group.rgb_t[c * plane];
        double* magnitude = &group.rgb_t[(3 + c) * plane];
        const double weight = wavelength.rgb_weight[c], absolute = std::abs(weight);
        for (std::size_t k = 0; k < plane; ++k) {
          target[k] += weight * group.d_t[k];
          magnitude[k] += absolute * group.d_t[k];
        }
      }
    }
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
  // the same sign, in the tail (on the 2N reference's scale, 1e-5 of the frame). A channel whose
  // display value is a small part of the magnitude of its wavelengths' contributions,
  // |R| < kStraddle sum_i |w_i| F_i, is where the sign can change inside the pixel: there the
  // display pixel is computed as the double path does, from the PSF pixels it covers, clamped one
  // by one. Elsewhere the sign is the same all over the pixel (checked against the double path on
  // the eye model's apertures, tests/glare_cpu_float_test.cpp) and the box mean is clamped.
  // Frame error against the float64 path with these (bench, eye model, 32 wavelengths): 2e-7 at
  // N = 256 to 1024; kStraddle = 0.3 left 8e-7 at N = 256 and 7e-6 at N = 128.
  constexpr double kStraddle = 0.5, kCoreRings = 8.0;
  // Around the core the rings of each wavelength sit at radii proportional to it (1.22, 2.23, ...
  // lambda / D, Born and Wolf 8.5.2), so a channel changes sign from one PSF pixel to the next
  // there while the box mean stays large: the display pixels within kCoreRings lambda_max / D of the
  // centre are always refined.
  const double longest_nm = spectral_samples(settings_.wavelength_samples).back().wavelength_nm;
  const double core_radius_display_px = kCoreRings * (longest_nm / settings_.reference_wavelength_nm) *
                                        (settings_.aperture_width_mm / pupil_diameter_mm) *
                                        settings_.psf_degrees_per_pixel / settings_.display_degrees_per_pixel;
  refined_pixels_ = 0;
  for (std::size_t k = 0; k < plane; ++k) {
    const double dx = static_cast<double>(k / m_px) - m_px / 2, dy = static_cast<double>(k % m_px) - m_px / 2;
    bool straddles = dx * dx + dy * dy <= core_radius_display_px * core_radius_display_px;
    for (int c = 0; c < 3; ++c) {
      const double net = total[c * plane + k], magnitude = total[(3 + c) * plane + k];
      if (magnitude > 0.0 && std::abs(net) < kStraddle * magnitude) straddles = true;
    }
    straddles_[k] = straddles ? 1 : 0;
    refined_pixels_ += straddles ? 1 : 0;
  }
  // rgb_t is transposed: index x * M + y.
  parallel_chunks(m_px, settings_.threads, [&](int first, int last) {
    for (int mx = first; mx < last; ++mx)
      for (int my = 0; my < m_px; ++my) {
        const std::size_t k = static_cast<std::size_t>(mx) * m_px + my;
        if (straddles_[k] == 0) continue;
        double sum[3] = {0.0, 0.0, 0.0}, rgb[3];
        for (const PsfOverlap& ox : box_[static_cast<std::size_t>(mx)])
          for (const PsfOverlap& oy : box_[static_cast<std::size_t>(my)]) {
            spectral_at(power, ox.input, oy.input, rgb);
            const double area = ox.fraction * oy.fraction;
            for (int c = 0; c < 3; ++c) sum[c] += area * std::max(0.0, rgb[c]);
          }
        for (int c = 0; c < 3; ++c) total[c * plane + k] = sum[c];
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
