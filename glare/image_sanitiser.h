#pragma once
// Explicit repair of an HDR image before convolution. Both backends refuse NaN, Inf and negative
// R, G, B (a clear error naming the counts); a caller that prefers to go on asks for this instead and
// is told what changed. Rules, per R, G, B value (alpha and depth are left alone):
//   NaN -> 0 (no light is the only value that adds none);
//   +Inf -> the cap (stated in the report): options.positive_infinity_cap, or, when that is 0, the
//           largest finite value of the image, so an infinite pixel is as bright as the brightest real one;
//   negative, -Inf included -> 0 (luminance cannot be negative; negatives come from filtering ringing).
#include <cstddef>
#include <string>

#include "core/image.h"

namespace glarelab {

struct SanitiseOptions {
  double positive_infinity_cap = 0.0;  // > 0: this value (image units, cd/m2); 0: the image's largest finite value
};

struct SanitiseReport {
  std::size_t nan_values = 0;                // counted per R, G, B value, not per pixel
  std::size_t positive_infinity_values = 0;
  std::size_t negative_values = 0;           // -Inf included
  std::size_t changed_pixels = 0;            // pixels with at least one changed value
  double infinity_cap = 0.0;                 // the value +Inf became
  bool changed() const { return changed_pixels > 0; }
  std::string describe() const;  // "sanitised: N NaN -> 0, M +Inf -> CAP, K negative -> 0 (P pixels)"
};

// Throws std::invalid_argument ("glare/image_sanitiser: ...") for a negative or non-finite cap.
ImageRGBA sanitise_image(const ImageRGBA& image, const SanitiseOptions& options = {}, SanitiseReport* report = nullptr);

}  // namespace glarelab
