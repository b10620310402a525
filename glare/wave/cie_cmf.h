#pragma once
// CIE 1931 2-degree colour matching functions by the multi-lobe piecewise-Gaussian fit of
// Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions", JCGT 2(2), 2013, section 2.1 (Eq. 2 and its table). Chosen over shipping the CIE
// table: Debian packages no CMF table for C++, and the fit is within a few percent of the peak,
// far below what the PSF's spectral sampling (32 samples) resolves.
#include <vector>

namespace glarelab {

struct Xyz {
  double x = 0.0, y = 0.0, z = 0.0;
};

Xyz cie1931_cmf(double wavelength_nm);

struct LinearRgb {
  double r = 0.0, g = 0.0, b = 0.0;
};

// XYZ (D65 white) to linear Rec.709 / sRGB primaries: IEC 61966-2-1:1999, section 5.2 matrix.
LinearRgb xyz_to_linear_rec709(const Xyz& xyz);

// CIE standard illuminant D65, relative spectral power (100 at 560 nm), CIE 015:2004 Table T.1
// at its 10 nm steps from 380 to 780 nm, read linearly between them (0 outside). D65 is the white
// of linear Rec.709: a pixel R = G = B has its chromaticity, so a white lamp in a frame has this
// spectrum.
double cie_d65_relative_power(double wavelength_nm);
constexpr double kD65FirstNm = 380.0, kD65LastNm = 780.0, kD65StepNm = 10.0;

// One wavelength of the chromatic blur with its CMF weight in linear Rec.709. Both compute backends
// (glare/wave/spectral_psf.cpp, glare/gl/psf.cpp) take their wavelengths and weights from here.
struct SpectralSample {
  double wavelength_nm = 0.0;
  LinearRgb weight;
};

// Ritschel et al. 2009, section 5: lambda_i = 380 nm + i (770 nm - 380 nm) / n, i = 0..n-1, for an
// equal-energy spectrum s(lambda) = 1. Throws std::invalid_argument for n < 1.
std::vector<SpectralSample> spectral_samples(int wavelength_count);

}  // namespace glarelab
