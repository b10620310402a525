#pragma once
// CIE 1931 2-degree colour matching functions by the multi-lobe piecewise-Gaussian fit of
// Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions", JCGT 2(2), 2013, section 2.1 (Eq. 2 and its table). Chosen over shipping the CIE
// table: Debian packages no CMF table for C++, and the fit is within a few percent of the peak,
// far below what the PSF's spectral sampling (32 samples) resolves.
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

}  // namespace glarelab
