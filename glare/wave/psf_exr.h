#pragma once
// PSFs as OpenEXR files (docs/ARCHITECTURE.md, "Images"): float channels, "Y" for a one-channel PSF or
// R, G, B for a spectral one, and the float header attribute degreesPerPixel.
#include <string>

#include "glare/wave/psf.h"

namespace glarelab {

void write_psf_exr(const std::string& path, const Psf& psf);
// Throws ImageError for files that are not square or lack degreesPerPixel. A "Y" file reads as one
// channel; RGB as three.
Psf read_psf_exr(const std::string& path);

}  // namespace glarelab
