#pragma once
// The per-pixel reference of the depth-of-field stage: every pixel spreads its own light over the
// elliptical kernel of its own depth (Kakimoto et al. 2007, Eq. 8, exact for each depth, no layers),
// accumulated in double. There is no occlusion: light from a far pixel reaches the image over a
// near object as it would if the near object were transparent, which is what distinguishes it from
// the layered stage at depth edges (stimuli/depth_of_field.h). The sum is divided by the kernel
// weight each pixel received, as the layered stage divides by coverage, so both renormalise the
// kernels at the frame's borders in the same way.
//
// Slow (pixels x kernel area), single-threaded: it exists to measure the layering's error in the
// tests and the benchmark. Kernels are built once per distinct depth value.
#include <vector>

#include "core/image.h"
#include "stimuli/depth_of_field.h"

namespace glarelab {

// The same inputs, checks and refusals as apply_depth_of_field; settings.tolerance_px and
// settings.threads are not used.
ImageRGBA depth_of_field_reference(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                   const DepthOfFieldSettings& settings);

// Differences of a result from the reference over R, G, B of every pixel (cd/m2): the largest, the
// mean absolute and that mean relative to the reference's mean value.
struct DepthOfFieldError {
  double max_abs_cd_m2 = 0.0;
  double mean_abs_cd_m2 = 0.0;
  double mean_relative = 0.0;
};
DepthOfFieldError depth_of_field_error(const ImageRGBA& result, const ImageRGBA& reference);

}  // namespace glarelab
