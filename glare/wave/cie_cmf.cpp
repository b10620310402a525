#include "glare/wave/cie_cmf.h"

#include <algorithm>
#include <array>
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

// CIE 015:2004, Table T.1, D65 at 380, 390, ..., 780 nm.
constexpr std::array<double, 41> kD65 = {
    49.9755, 54.6482, 82.7549, 91.4860, 93.4318, 86.6823, 104.865, 117.008, 117.812, 114.861, 115.923,
    108.811, 109.354, 107.802, 104.790, 107.689, 104.405, 104.046, 100.000, 96.3342, 95.7880, 88.6856,
    90.0062, 89.5991, 87.6987, 83.2886, 83.6992, 80.0268, 80.2146, 82.2778, 78.2842, 69.7213, 71.6091,
    74.3490, 61.6040, 69.8856, 75.0870, 63.5927, 46.4182, 66.8054, 63.3828};

}  // namespace

double cie_d65_relative_power(double wavelength_nm) {
  const double at = (wavelength_nm - kD65FirstNm) / kD65StepNm;
  if (!(at >= 0.0) || at > static_cast<double>(kD65.size() - 1)) return 0.0;
  const auto i = std::min(static_cast<std::size_t>(at), kD65.size() - 2);
  const double t = at - static_cast<double>(i);
  return (1.0 - t) * kD65[i] + t * kD65[i + 1];
}

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
