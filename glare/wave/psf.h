#pragma once
// A point-spread function sampled on a square grid centred on pixel (size/2, size/2), with its
// angular pixel size (docs/ARCHITECTURE.md, "Images"). Channels are "Y" (one wavelength) or linear
// Rec.709 "R,G,B" (spectral); each channel sums to 1.
#include <stdexcept>
#include <string>
#include <vector>

namespace glarelab {

// The wavelength of the wave-optics PSF grid: Ritschel et al. 2009's reference wavelength (section 5).
inline constexpr double kReferenceWavelengthNm = 575.0;

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

// The aperture transmits no light (the lids cover the pupil in a blink, or the pupil lies outside
// the grid): the PSF is undefined (0 / 0). Thrown by both backends' psf(), so a caller tells a closed
// eye from an error by type and from the same rasterised pixels the PSF would have used.
class ClosedApertureError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace glarelab
