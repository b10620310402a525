#include "glare/wave/cie_cmf.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace glarelab {
namespace {

// Piecewise Gaussian g(lambda; mu, s1, s2) of Wyman et al. 2013, Eq. 2: width s1 below mu, s2 above.
double lobe(double wavelength_nm, double mu, double sigma_below, double sigma_above) {
  const double t = (wavelength_nm - mu) / (wavelength_nm < mu ? sigma_below : sigma_above);
  return std::exp(-0.5 * t * t);
}

}  // namespace

Xyz cie1931_cmf(double l) {
  // Wyman, Sloan, Shirley 2013, section 2.1, the multi-lobe fit's parameters (nm).
  Xyz cmf;
  cmf.x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2);
  cmf.y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
  cmf.z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
  return cmf;
}

LinearRgb xyz_to_linear_rec709(const Xyz& c) {
  return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
          0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

std::vector<SpectralSample> spectral_samples(int wavelength_count) {
  if (wavelength_count < 1)
    throw std::invalid_argument("glare/wave/cie_cmf: wavelength count " + std::to_string(wavelength_count) + " is below 1");
  std::vector<SpectralSample> samples;
  for (int i = 0; i < wavelength_count; ++i) {
    const double wavelength_nm = 380.0 + i * (770.0 - 380.0) / wavelength_count;
    samples.push_back({wavelength_nm, xyz_to_linear_rec709(cie1931_cmf(wavelength_nm))});
  }
  return samples;
}

}  // namespace glarelab
