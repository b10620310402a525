#pragma once
// Spectral weights for the chromatic blur (Ritschel et al. 2009, section 5) on the GL path: the
// CIE 1931 2-degree colour matching functions by the multi-lobe analytic fit of Wyman, Sloan and
// Shirley 2013 ("Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2),
// Eq. 2 and Table 1), taken to linear Rec.709 (IEC 61966-2-1 XYZ-to-RGB matrix, D65 white).
// Kept separate from any tabulated CMF of the CPU path; the two are to be unified in one header.
#include <vector>

namespace glarelab {

struct CieXyz {
  double x = 0.0, y = 0.0, z = 0.0;
};

// x-bar, y-bar, z-bar at a wavelength in nanometres (the fit is valid over 360-830 nm).
CieXyz cie1931_cmf_fit(double wavelength_nm);

// Linear Rec.709 RGB from CIE XYZ (IEC 61966-2-1:1999, section 5.2, the inverse of the sRGB matrix).
struct LinearRgb {
  double r = 0.0, g = 0.0, b = 0.0;
};
LinearRgb xyz_to_linear_rec709(const CieXyz& xyz);

struct SpectralSample {
  double wavelength_nm = 0.0;
  LinearRgb weight;  // the CMFs at this wavelength, in linear Rec.709
};

// Ritschel et al. 2009, section 5: lambda_i = 380 nm + i (770 nm - 380 nm) / n, i = 0..n-1, for an
// equal-energy spectrum s(lambda) = 1. Throws std::invalid_argument for n < 1.
std::vector<SpectralSample> spectral_samples(int wavelength_count);

}  // namespace glarelab
