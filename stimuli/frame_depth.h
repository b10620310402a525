#pragma once
// The depth map of a composed frame, for the depth-of-field stage (stimuli/depth_of_field.h): where
// a placed scene carries a Z channel, its depths; where it does not, and on the background, the
// display's viewing distance (a picture on the screen). Scenes are drawn at their native pixel size
// (stimuli/layout.h), so a scene pixel's depth lands on exactly one display pixel.
//
// Through spectacles the frame is warped (stimuli/spectacle_warp.h), so its depth map must be too:
// each output pixel takes the depth of the scene pixel nearest to where the lens sends its line of
// sight (the d line's mapping, which alpha follows in the warp as well). Nearest, not bilinear: a
// depth is not a colour, and blending a near and a far depth at an edge would invent a surface
// between them, blurred by a kernel neither side has.
#include <optional>
#include <vector>

#include "core/image.h"
#include "core/pixel_rect.h"
#include "glare/refraction/spectacle_lens.h"
#include "stimuli/spectacle_warp.h"

namespace glarelab {

struct PlacedDepth {
  const ImageRGBA* scene = nullptr;  // its `depth` (metres from the eye), or none: background depth
  PixelRect rect;                    // where the image goes
  PixelRect clip;                    // what of it is drawn
};

// width_px x height_px depths (row 0 at the top), later placements over earlier ones.
std::vector<float> composed_depth_m(int width_px, int height_px, float background_depth_m,
                                    const std::vector<PlacedDepth>& placed);

// The depth map as seen through the lens (see above); `outside_depth_m` where the lens looks past
// the frame. Throws as grid_source_map (stimuli/spectacle_warp.h) does.
std::vector<float> depth_through_spectacles(const std::vector<float>& depth_m, const SpectacleLens& lens,
                                            const SpectacleFrame& frame, std::optional<double> scene_distance_mm,
                                            float outside_depth_m, int threads);

}  // namespace glarelab
