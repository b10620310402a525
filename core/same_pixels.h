#pragma once
// Whether two images hold the same colour values bit for bit, for the caches that keep work done
// for a frame while the same frame comes again (the analytic far glare, the lenticular halo's ring,
// the glare stage's hybrid parts). Bits, not values: a NaN or a signed zero makes a new frame,
// never a false match.
#include <cstring>

#include "core/image.h"

namespace glarelab {

inline bool same_pixel_bits(const ImageRGBA& a, const ImageRGBA& b) {
  return a.width_px == b.width_px && a.height_px == b.height_px && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

}  // namespace glarelab
