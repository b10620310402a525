#pragma once
// The smallest and largest Rec.709 luminance of a frame's pixels, for the glare stage's visibility
// bound (stimuli/glare_stage.h).
#include <utility>

#include "core/image.h"

namespace glarelab {

// (0, 0) when empty; each pixel's luminance in double as core/image.h's max_luminance; a frame of
// nothing but NaN gives a largest of 0, as max_luminance does.
std::pair<double, double> luminance_range(const ImageRGBA& image);

}  // namespace glarelab
