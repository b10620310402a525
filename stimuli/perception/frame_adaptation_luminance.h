#pragma once
// The luminance one frame asks the eye to adapt to (Luidolt 2020, section 5.1), in cd/m2:
//   1. each pixel's luminance (Eq. 5.1, Y = 0.2125 R + 0.7154 G + 0.0721 B, Poynton's rounding of
//      the Rec.709 weights) is weighted by a 2D Gaussian centred on the gaze point, "so that lights
//      at the periphery have little to no influence";
//   2. the weighted frame is resampled to 128 x 128 (exact area overlap of pixels);
//   3. a Gaussian pyramid is built from 128 x 128 down to 16 x 16 (the thesis' "four steps";
//      Burt and Adelson's 5-tap binomial [1 4 6 4 1] / 16, edges clamped, every second sample kept);
//   4. the 16 x 16 level is averaged to one value.
// The thesis averages the weighted colours; a plain average of w Y would call a uniform 10 cd/m2
// field darker than 10 cd/m2. The weights w go through the same resampling and pyramid and the
// result is mean(w Y) / mean(w), so a uniform field of Y adapts to Y exactly (both are the same
// linear operations, so the quotient is a weighted mean of the frame's luminances).
//
// The Gaussian's width is not given in the thesis. The default, sigma = 1/8 of the frame width,
// follows from the thesis' own numbers: (a) the 16 x 16 top level must resolve the weighting, and
// with sigma = two cells of that grid (2/16 of the width) the weight falls smoothly across the
// cells instead of living inside one; (b) on the thesis' headset (104 degrees across, section 5.3.2)
// it is 13 degrees, so a light 30 degrees from the gaze point, in the periphery, counts
// exp(-(30/13)^2 / 2) = 7 % of the same light at the gaze point ("little to no influence"), while
// the central 10-15 degrees where the gaze moves in a fixation-and-look scene keep most weight.
// The Gaussian is circular on the screen: distances are measured in units of the frame width in
// both directions.
#include "core/image.h"
#include "core/perception_settings.h"
#include "core/vector_isa.h"

namespace glarelab {

// Luidolt Eq. 5.1 (after Poynton 1998): luminance of linear Rec.709 RGB with a D65 white, cd/m2.
inline double luidolt_luminance_cd_m2(double r, double g, double b) {
  return 0.2125 * r + 0.7154 * g + 0.0721 * b;
}

// The adapted-to luminance of one frame in cd/m2. Gaze in normalised display coordinates (0..1,
// origin at the top left, y down: docs/TRACKERS.md); a gaze outside the frame is allowed (the
// weight then falls off from the frame's edge). Throws std::invalid_argument for an empty frame,
// a non-finite gaze or a sigma that is not finite and > 0, naming the value.
double frame_adaptation_luminance_cd_m2(const ImageRGBA& frame, double gaze_x, double gaze_y,
                                        const AdaptationWeighting& weighting = {});

// The same luminance in one pass over the float32 frame, split over `threads` row chunks
// (core/parallel_for.h): the gaze Gaussian is separable (one exponential per row and one per column
// instead of one per pixel), and so are the resampling, the pyramid and the mean, which compose to
// one weight per column and one per row, so each pixel is read once and takes one weight. What
// sessions run (stimuli/perception/perception_stages_float.h); the function above is its reference
// (tests/perception_float_test.cpp: within 1e-12 relative). The result does not depend on `threads`.
// `isa`: the form of the row sums (core/vector_isa.h; both within 1e-12, each test runs both); one
// this CPU does not run takes the SSE2 form.
double frame_adaptation_luminance_float_cd_m2(const ImageRGBA& frame, double gaze_x, double gaze_y,
                                              const AdaptationWeighting& weighting, int threads,
                                              VectorIsa isa = widest_vector_isa());

// The weight the gaze Gaussian gives the pixel (x, y) of a width x height frame (pixel centres at
// x + 0.5, y + 0.5); exposed for tests and the documentation's numbers.
double gaze_adaptation_weight(int x, int y, int width_px, int height_px, double gaze_x, double gaze_y,
                              double sigma_frame_widths);

}  // namespace glarelab
