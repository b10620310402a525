#include "glare/wave/spectral_accumulation.h"

#include <cmath>
#include <stdexcept>
#include <string>

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

void accumulate_resampled_psf(const Psf& source, double scale, const Xyz& weight, XyzPlanes& sum) {
  const int n = sum.size_px;
  if (source.size_px != n || source.channels != 1)
    throw std::invalid_argument("glare/wave/spectral_accumulation: the source PSF must be one channel on the sum's grid");
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  const double centre = n / 2;
  const double jacobian = scale * scale;
  for (int y = 0; y < n; ++y) {
    const double sy = (y - centre) * scale + centre;
    for (int x = 0; x < n; ++x) {
      const double value = jacobian * bilinear(source, (x - centre) * scale + centre, sy);
      if (value == 0.0) continue;
      const std::size_t index = static_cast<std::size_t>(y) * n + x;
      sum.values[index] += weight.x * value;
      sum.values[plane + index] += weight.y * value;
      sum.values[2 * plane + index] += weight.z * value;
    }
  }
}

SpectralPsfResult rec709_psf_from_xyz(const XyzPlanes& sum, double degrees_per_pixel, const char* subsystem) {
  const int n = sum.size_px;
  const std::size_t plane = static_cast<std::size_t>(n) * n;
  const std::vector<double>& xyz = sum.values;
  SpectralPsfResult result;
  result.psf.size_px = n;
  result.psf.channels = 3;
  result.psf.degrees_per_pixel = degrees_per_pixel;
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
    if (!(positive[c] > 0.0)) throw std::runtime_error(std::string(subsystem) + ": a Rec.709 channel has no positive energy");
    result.clamped_negative_fraction[c] = negative[c] / positive[c];
    const double inverse = 1.0 / positive[c];
    for (std::size_t k = 0; k < plane; ++k) result.psf.values[c * plane + k] *= inverse;
  }
  return result;
}

}  // namespace glarelab
