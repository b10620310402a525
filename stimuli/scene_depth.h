#pragma once
// Per-pixel depth of a scene, in metres from the observer's eye, for the depth-of-field stage
// (stimuli/depth_of_field.h). An EXR scene may carry a "Z" channel (core/exr_io.h loads it into
// ImageRGBA::depth); a scene without one is a picture on the display and sits at its viewing
// distance.
//
// What a depth may be: a positive finite number of metres, or +infinity for a surface at optical
// infinity (a sky, a far landscape: vergence 0 dioptres, which is where an emmetrope's relaxed
// eye focuses). NaN, -infinity, zero and negative depths are refused: none of them is a place a
// surface can be, and the blur of Kakimoto et al. 2007 (Eq. 8) depends on the vergence 1 / depth.
#include <string>
#include <vector>

#include "core/display_spec.h"
#include "core/image.h"

namespace glarelab {

// Whether every depth is > 0 (+inf included; NaN, zero, negative and -inf are not): what
// check_scene_depth accepts, in one vector pass without naming the first bad pixel.
bool all_depths_positive(const std::vector<float>& depth_m);

// Throws ImageError "stimuli/scene_depth: FILE: Z at pixel (x, y) is VALUE; ..." naming the first
// bad pixel in row order (row 0 at the top), or the count mismatch when depth_m does not hold
// width_px * height_px values. `file` names the source in the message.
void check_scene_depth(const std::vector<float>& depth_m, int width_px, int height_px, const std::string& file);

// The scene's depth map (metres, one value a pixel, row 0 at the top): its Z channel, checked as
// above, or, without one, every pixel at the display's viewing distance.
std::vector<float> scene_depth_m(const ImageRGBA& image, const std::string& file, const DisplaySpec& display);

// Vergence of a depth, 1 / depth_m dioptres; 0 for +infinity.
inline double vergence_dioptres(double depth_m) { return 1.0 / depth_m; }

}  // namespace glarelab
