#include "glare/image_sanitiser.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace glarelab {

std::string SanitiseReport::describe() const {
  std::ostringstream text;
  text << "sanitised: " << nan_values << " NaN -> 0, " << positive_infinity_values << " +Inf -> " << infinity_cap << ", "
       << negative_values << " negative -> 0 (R, G, B values in " << changed_pixels << " pixels)";
  return text.str();
}

ImageRGBA sanitise_image(const ImageRGBA& image, const SanitiseOptions& options, SanitiseReport* report) {
  if (!(options.positive_infinity_cap >= 0.0) || !std::isfinite(options.positive_infinity_cap))
    throw std::invalid_argument("glare/image_sanitiser: the +Inf cap must be finite and >= 0");
  const std::size_t pixels = static_cast<std::size_t>(image.width_px) * static_cast<std::size_t>(image.height_px);
  double cap = options.positive_infinity_cap;
  if (cap == 0.0)
    for (std::size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) {
        const float value = image.rgba[4 * p + static_cast<std::size_t>(c)];
        if (std::isfinite(value) && value > cap) cap = value;
      }
  SanitiseReport counts;
  counts.infinity_cap = static_cast<double>(static_cast<float>(cap));
  ImageRGBA out = image;
  for (std::size_t p = 0; p < pixels; ++p) {
    bool changed = false;
    for (int c = 0; c < 3; ++c) {
      float& value = out.rgba[4 * p + static_cast<std::size_t>(c)];
      if (std::isnan(value)) {
        value = 0.0f;
        ++counts.nan_values;
      } else if (std::isinf(value) && value > 0.0f) {
        value = static_cast<float>(cap);
        ++counts.positive_infinity_values;
      } else if (value < 0.0f) {
        value = 0.0f;
        ++counts.negative_values;
      } else {
        continue;
      }
      changed = true;
    }
    counts.changed_pixels += changed ? 1 : 0;
  }
  if (report) *report = counts;
  return out;
}

}  // namespace glarelab
