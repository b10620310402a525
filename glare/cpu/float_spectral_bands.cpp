// CpuFloatSpectralPsf's matrices, built once per settings: per wavelength the bilinear neighbours
// of each scaled PSF position (glare/wave/spectral_psf.cpp's interpolation) and the band rows of W_i = R B_i
// (glare/cpu/float_spectral_psf.h), and the buffers compute() works in (glare/cpu/float_spectral_psf.cpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "glare/wave/cie_cmf.h"
#include "glare/cpu/float_spectral_psf.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {

CpuFloatSpectralPsf::CpuFloatSpectralPsf(const CpuFloatSpectralSettings& settings) : settings_(settings) {
  const int n = settings.grid_px;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/cpu/float_spectral_psf: grid size must be even and >= 2");
  if (!(settings.reference_wavelength_nm > 0.0))
    throw std::invalid_argument("glare/cpu/float_spectral_psf: reference wavelength must be > 0");
  check_psf_fits_display(n, settings.psf_degrees_per_pixel, settings.display_degrees_per_pixel);
  display_px_ = display_psf_size_px(n, settings.psf_degrees_per_pixel, settings.display_degrees_per_pixel);
  const int m_px = display_px_;
  box_ = psf_overlap_weights(n, settings.psf_degrees_per_pixel, m_px, settings.display_degrees_per_pixel);
  const auto& box = box_;
  const double centre = n / 2;
  std::vector<double> dense(static_cast<std::size_t>(n), 0.0);
  for (const SpectralSample& sample : spectral_samples(settings.wavelength_samples)) {
    Wavelength wavelength;
    // glare/wave/spectral_psf.cpp: x_i = (x - c) lambda_ref / lambda + c, value times the Jacobian scale^2.
    const double scale = settings.reference_wavelength_nm / sample.wavelength_nm;
    const double jacobian = scale * scale;
    wavelength.rgb_weight[0] = jacobian * sample.weight.r;
    wavelength.rgb_weight[1] = jacobian * sample.weight.g;
    wavelength.rgb_weight[2] = jacobian * sample.weight.b;
    for (int c = 0; c < 3; ++c) wavelength.rgb_weight_float[c] = static_cast<float>(wavelength.rgb_weight[c]);
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
    // interpolate_along_row's vector form: eight consecutive outputs read at most 16 consecutive
    // source values: they span at most 7 scale + 2, within 15 while scale <= 13/7 (lambda_ref / lambda
    // is at most about 1.5).
    wavelength.compact = true;
    for (int x = 0; x + 7 < n; ++x)
      if (wavelength.index1[static_cast<std::size_t>(x + 7)] - wavelength.index0[static_cast<std::size_t>(x)] > 15)
        wavelength.compact = false;
    wavelength.first_column = n;
    for (int m = 0; m < m_px; ++m) {
      // Row m of W = R B: sum over the PSF pixels x in display pixel m of their bilinear weights.
      int first = n, last = -1;
      for (const PsfOverlap& overlap : box[static_cast<std::size_t>(m)]) {
        const double position = (overlap.input - centre) * scale + centre;
        const double floor_position = std::floor(position);
        const int x0 = static_cast<int>(floor_position);
        const double fraction = position - floor_position;
        // Out-of-grid neighbours read 0, as glare/wave/spectral_psf.cpp's bilinear does.
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
  for (std::size_t w = 0; w < wavelengths_.size(); ++w)
    if (wavelengths_[w].last_column >= wavelengths_[w].first_column) active_.push_back(static_cast<int>(w));
  sum_weights_.assign(6 * active_.size(), 0.0);
  for (std::size_t s = 0; s < active_.size(); ++s)
    for (int c = 0; c < 3; ++c) {
      const double weight = wavelengths_[static_cast<std::size_t>(active_[s])].rgb_weight[c];
      sum_weights_[(2 * c) * active_.size() + s] = weight;
      sum_weights_[(2 * c + 1) * active_.size() + s] = std::abs(weight);
    }
  scratch_.resize(static_cast<std::size_t>(std::max(1, settings.threads)));
  for (TileScratch& scratch : scratch_) {
    scratch.row.assign(static_cast<std::size_t>(kTile) * n, 0.0f);
    scratch.tile_t.assign(static_cast<std::size_t>(kTile) * n, 0.0f);
    scratch.tile_d.assign(active_.size() * m_px * kTile, 0.0f);
  }
  totals_.assign(6 * static_cast<std::size_t>(m_px) * m_px, 0.0);
  straddles_.assign(static_cast<std::size_t>(m_px) * m_px, 0);
  negative_.assign(straddles_.size(), 0);
  along_y_any_.assign(straddles_.size(), 0);
  along_y_all_.assign(straddles_.size(), 0);
}

}  // namespace glarelab
