#include "glare/spectral_psf.h"

#include <cmath>
#include <stdexcept>

#include "glare/cie_cmf.h"

namespace glarelab {
namespace {

double bilinear(const Psf& psf, double x, double y) {
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  const double fx = x - fx0, fy = y - fy0;
  auto value = [&](int xi, int yi) {
    if (xi < 0 || yi < 0 || xi >= psf.size_px || yi >= psf.size_px) return 0.0;
    return psf.at(0, xi, yi);
  };
  return (1 - fy) * ((1 - fx) * value(x0, y0) + fx * value(x0 + 1, y0)) +
         fy * ((1 - fx) * value(x0, y0 + 1) + fx * value(x0 + 1, y0 + 1));
}

}  // namespace

SpectralPsfResult spectral_psf_from_reference(const Psf& reference, const SpectralPsfOptions& options) {
  if (reference.channels != 1) throw std::invalid_argument("glare/spectral_psf: the reference PSF must have one channel");
  if (options.wavelength_samples < 1) throw std::invalid_argument("glare/spectral_psf: need at least one wavelength sample");
  if (!(options.reference_wavelength_nm > 0.0)) throw std::invalid_argument("glare/spectral_psf: reference wavelength must be > 0");
  const int n = reference.size_px;
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  std::vector<double> xyz(3 * plane, 0.0);
  const double centre = n / 2;
  for (const SpectralSample& sample : spectral_samples(options.wavelength_samples)) {
    // Ritschel et al. 2009, section 5: lambda_i = 380 + i (770 - 380) / n nm (cie_cmf.h).
    const double wavelength_nm = sample.wavelength_nm;
    const Xyz weight = cie1931_cmf(wavelength_nm);
    const double scale = options.reference_wavelength_nm / wavelength_nm;  // x_i = x lambda_ref / lambda_i
    const double jacobian = scale * scale;
    for (int y = 0; y < n; ++y) {
      const double sy = (y - centre) * scale + centre;
      for (int x = 0; x < n; ++x) {
        const double value = jacobian * bilinear(reference, (x - centre) * scale + centre, sy);
        if (value == 0.0) continue;
        const std::size_t index = static_cast<std::size_t>(y) * n + x;
        xyz[index] += weight.x * value;
        xyz[plane + index] += weight.y * value;
        xyz[2 * plane + index] += weight.z * value;
      }
    }
  }
  SpectralPsfResult result;
  result.psf.size_px = n;
  result.psf.channels = 3;
  result.psf.degrees_per_pixel = reference.degrees_per_pixel;
  result.psf.values.assign(3 * plane, 0.0);
  double positive[3] = {0, 0, 0}, negative[3] = {0, 0, 0};
  for (std::size_t k = 0; k < plane; ++k) {
    const LinearRgb rgb = xyz_to_linear_rec709({xyz[k], xyz[plane + k], xyz[2 * plane + k]});
    const double channel[3] = {rgb.r, rgb.g, rgb.b};
    for (int c = 0; c < 3; ++c) {
      if (channel[c] >= 0.0) {
        positive[c] += channel[c];
        result.psf.values[c * plane + k] = channel[c];
      } else {
        negative[c] -= channel[c];
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    if (!(positive[c] > 0.0)) throw std::runtime_error("glare/spectral_psf: a Rec.709 channel has no positive energy");
    result.clamped_negative_fraction[c] = negative[c] / positive[c];
    const double inverse = 1.0 / positive[c];
    for (std::size_t k = 0; k < plane; ++k) result.psf.values[c * plane + k] *= inverse;
  }
  return result;
}

}  // namespace glarelab
