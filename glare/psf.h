#pragma once
// A point-spread function sampled on a square grid centred on pixel (size/2, size/2), with its
// angular pixel size (DESIGN.md image contract). Channels are "Y" (one wavelength) or linear
// Rec.709 "R,G,B" (spectral); each channel sums to 1.
#include <string>
#include <vector>

namespace glarelab {

struct Psf {
  int size_px = 0;                 // width = height
  double degrees_per_pixel = 0.0;  // visual angle of one PSF pixel
  int channels = 1;                // 1 (Y) or 3 (R, G, B)
  std::vector<double> values;      // channel-major: values[c * size * size + y * size + x], row 0 at the top

  double& at(int channel, int x, int y) { return values[(static_cast<std::size_t>(channel) * size_px + y) * size_px + x]; }
  double at(int channel, int x, int y) const {
    return values[(static_cast<std::size_t>(channel) * size_px + y) * size_px + x];
  }
};

}  // namespace glarelab
