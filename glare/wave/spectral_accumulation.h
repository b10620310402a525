#pragma once
// The two steps every CPU spectral PSF shares (Ritschel et al. 2009, section 5; docs/GLARE_OPTICS.md
// section 5): adding one wavelength's PSF, resampled onto the reference wavelength's angular grid and
// weighted with the CIE 1931 CMFs, into an XYZ image; and turning that XYZ image into linear Rec.709
// channels that each sum to 1. glare/wave/spectral_psf.cpp (one reference PSF scaled per wavelength) and
// glare/wave/chromatic_psf.cpp (one FFT per wavelength, each with its own defocus) both use them.
#include <vector>

#include "glare/wave/cie_cmf.h"
#include "glare/wave/psf.h"

namespace glarelab {

struct SpectralPsfResult {
  Psf psf;  // 3 channels R, G, B, each sums to 1, same grid and degrees_per_pixel as the reference
  // Per channel: sum of the clamped negative values / sum of the positive values.
  double clamped_negative_fraction[3] = {0.0, 0.0, 0.0};
};

// XYZ planes (x, then y, then z, each N x N) of a spectral PSF being summed.
struct XyzPlanes {
  int size_px = 0;
  std::vector<double> values;  // 3 N^2
  explicit XyzPlanes(int n) : size_px(n), values(3 * static_cast<std::size_t>(n) * n, 0.0) {}
};

// Adds weight * F to `sum`, where F is the one-channel PSF `source` (same N) read at
// x_source = (x - N/2) scale + N/2 (and y likewise) by bilinear interpolation (zero outside) and
// multiplied by the Jacobian scale^2, which keeps its energy as the pixel area changes.
// scale = lambda_ref / lambda: a PSF computed at lambda has pixels of lambda / W radians, the
// reference grid pixels of lambda_ref / W, so reference pixel x lies at source pixel x lambda_ref / lambda;
// and the reference PSF itself, read at that scale, is the Fraunhofer PSF at lambda.
void accumulate_resampled_psf(const Psf& source, double scale, const Xyz& weight, XyzPlanes& sum);

// The summed XYZ converted to linear Rec.709; negative values (spectral colours outside the gamut)
// clamped to 0 before each channel is normalised to sum 1, the clamped fraction reported. Throws
// std::runtime_error (naming `subsystem`) when a channel has no positive energy.
SpectralPsfResult rec709_psf_from_xyz(const XyzPlanes& sum, double degrees_per_pixel, const char* subsystem);

}  // namespace glarelab
