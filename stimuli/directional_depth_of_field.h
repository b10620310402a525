#pragma once
// Depth of field when the eye's power error depends on the line of sight as well as on the depth:
// behind a spectacle lens each pixel's direction passes through its own zone of the lens (oblique
// astigmatism, a progressive lens' near zone below the fitting cross), and Kakimoto et al. 2007
// trace the wavefront from each voxel through the lens along its own ray (section 4.3, Table 1),
// so the blur field of Eqs. 8-9 varies across the image as well as in depth.
//
// Model: per display region. The frame is split into nx x ny equal rectangles; each is blurred by
// the depth-of-field stage (stimuli/depth_of_field.h) with the error function of the line of sight
// through the region's centre, on the region widened by a margin at least as large as the largest
// blur any of its depths gets, so every pixel of the region receives the light of all its
// neighbours exactly as a whole-frame pass with that function would give it. The regions are
// chosen like the depth layers (stimuli/depth_layers.h): the axes are halved in turn until, at the
// scene's nearest and farthest depth, no region edge's error differs from the region centre's by
// more than tolerance_px of blur (spectral norm of the difference times r_p / radians per pixel), up
// to max_regions_per_axis. An error that does not depend on the direction is one region: the
// stage itself, bit for bit.
//
// What this leaves out: a pixel is blurred with its region's error, not its own (the report gives
// the largest difference, at the regions' corners); near a region's edge a source pixel's light is
// spread with the kernel of the region it lands in, which differs from its own by at most that.
#include <functional>
#include <vector>

#include "core/image.h"
#include "glare/refraction/dioptric_power.h"
#include "stimuli/depth_of_field.h"

namespace glarelab {

// The eye's residual power error (observer frame, dioptres) as a function of distance along the
// line of sight through the continuous pixel position (x_px, y_px) (pixel i's centre at i, row 0 at
// the top). Made once per region and probe point, so a caller can trace its lens there once.
using EyeErrorAlongSightLine = std::function<EyeErrorAtDistance(double x_px, double y_px)>;

struct DirectionalDepthOfFieldSettings {
  double degrees_per_pixel = 0.0;
  double pupil_radius_m = 0.0;
  EyeErrorAlongSightLine residual_error;
  double tolerance_px = kDefaultLayerTolerancePx;  // of the depth layers and of the regions
  int max_regions_per_axis = 32;
  int threads = 1;
};

struct DirectionalDepthOfFieldReport {
  int regions_x = 1;
  int regions_y = 1;
  int layers = 0;                      // summed over the regions
  int most_layers_in_a_region = 0;
  int margin_px = 0;                   // the largest margin a region was widened by
  double max_direction_error_px = 0.0;  // largest blur error between a region corner's error and
                                        // the region centre's (at the nearest and farthest depth)
  double max_layer_error_px = 0.0;     // the depth layers' own (DepthOfFieldReport::max_blur_error_px)
};

// As apply_depth_of_field (the same refusals, "stimuli/depth_of_field"), plus
// std::invalid_argument "stimuli/directional_depth_of_field: ..." for max_regions_per_axis < 1. The
// result does not depend on `threads`.
ImageRGBA apply_directional_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                           const DirectionalDepthOfFieldSettings& settings,
                                           DirectionalDepthOfFieldReport* report = nullptr);

}  // namespace glarelab
