#pragma once
// Depth layers for the depth-of-field stage: the scene's depths grouped in dioptric space (vergence
// 1 / depth) so that one blur ellipse serves a whole layer.
//
// The rule. The blur of Kakimoto et al. 2007 (Eq. 8) maps pupil point p (|p| <= r_p) to the
// angle E p, E the eye's residual power error for that depth. Drawing a pixel of vergence v with the
// blur of another vergence w moves every ray's landing point by at most
//   ||E(v) - E(w)|| r_p / (radians per pixel)   pixels   (|| || the spectral norm),
// the blur error. A layer gathers the scene's vergences, far to near, while the blur error between
// its nearest and farthest member stays within 2 tolerance_px, and is drawn with the blur of the
// middle of its vergence range: when E is affine in vergence over the layer (a fixed accommodation:
// E(v) = E0 - v I), no member's blur is off by more than tolerance_px. The largest error each layer
// really makes is measured and reported. Only vergences that occur in the scene make layers: empty
// stretches of depth cost nothing, and a flat scene is one layer.
//
// Blending. A pixel between the middles of two neighbouring layers is drawn with the blend of their
// two kernels, weighted linearly by where its vergence lies between the middles (its light and
// coverage split between the two layers). A kernel changes smoothly as it grows (the rim's coverage
// of each pixel it crosses) except where its rim enters a new pixel, so the blend follows the kernel
// in between more closely than the nearer layer's kernel alone: about half the error against the
// per-pixel reference (docs/DEPTH_OF_FIELD.md), for about a tenth more time. Layers blend when
// their middles' blur error is within 4 tolerance_px (twice the span of one layer: layers that
// follow each other without an empty stretch of depth); across a larger gap (two planes) a pixel
// keeps its own layer's kernel.
//
// Why 0.25 px: the kernel is drawn on whole pixels; moving a ray's landing point by a quarter pixel
// moves a blurred edge by at most a quarter pixel and changes a pixel's coverage by at most about a
// quarter of the ellipse's rim through it, well under the pixel steps the display can show.
// A layer whose own blur is within the tolerance (semi-major axis <= tolerance_px) is passed through
// unblurred: an ellipse that small lies inside its pixel, so its kernel is the identity anyway.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "glare/refraction/dioptric_power.h"
#include "stimuli/elliptical_kernel.h"

namespace glarelab {

// The eye's residual power error (dioptres, observer frame) for a point at distance_m from the eye
// (+inf for a point at infinity). Built elsewhere from a refraction and the accommodation; an
// emmetrope accommodated at z_a has (1 / z_a - 1 / distance_m) I.
using EyeErrorAtDistance = std::function<DioptricPower(double distance_m)>;

inline constexpr double kDefaultLayerTolerancePx = 0.25;

// Pixels to radians: the blur's scale on the image.
struct BlurGeometry {
  double degrees_per_pixel = 0.0;
  double pupil_radius_m = 0.0;
  // Pixels a ray moves per dioptre of power error: r_p / radians_per_pixel.
  double pixels_per_dioptre() const;
};

struct DepthLayer {
  double far_vergence_dioptres = 0.0;   // smallest vergence among the layer's pixels
  double near_vergence_dioptres = 0.0;  // largest
  double vergence_dioptres = 0.0;       // the middle, whose blur the layer is drawn with
  PixelBlurEllipse ellipse;             // that blur on the image
  double max_blur_error_px = 0.0;       // largest blur error of a member vergence drawn with the
                                        // layer's kernel alone (see above); blending lowers it
  bool blurred = false;                 // false: semi-major <= tolerance, passed through
  std::size_t pixel_count = 0;          // pixels whose vergence lies in the layer's range
  DioptricPower error;                  // the eye's error at the middle vergence
};

struct DepthLayerPlan {
  std::vector<DepthLayer> layers;             // far to near (ascending vergence)
  std::vector<std::uint32_t> layer_of_pixel;  // index into layers, row-major like the depth map
  // The neighbouring layer each pixel is blended with and the share of its light that goes there
  // (in [0, 1); 0, with blend_layer_of_pixel == layer_of_pixel, for none).
  std::vector<std::uint32_t> blend_layer_of_pixel;
  std::vector<float> blend_weight;
};

// Middles whose blur error is within this many tolerances blend (see above).
inline constexpr double kBlendSpanTolerances = 4.0;

// depth_m: one value a pixel, checked (stimuli/scene_depth.h: positive, +inf allowed).
// Throws std::invalid_argument naming "stimuli/depth_layers" for a geometry that is not positive
// and finite, tolerance_px <= 0, or an error function that returns a non-finite power.
DepthLayerPlan plan_depth_layers(const std::vector<float>& depth_m, const BlurGeometry& geometry,
                                 const EyeErrorAtDistance& error, double tolerance_px = kDefaultLayerTolerancePx,
                                 int threads = 1);

// The same into `plan`, whose vectors' memory is reused (DepthOfFieldBuffers).
void plan_depth_layers(const std::vector<float>& depth_m, const BlurGeometry& geometry, const EyeErrorAtDistance& error,
                       double tolerance_px, int threads, DepthLayerPlan& plan);

// Pixels [first, end) of a frame row with the same layer, blend layer and blend weight
// (DepthLayerPlan's per-pixel values): a stage reads the layers' pixels a run at a time.
struct PixelRun {
  int first = 0, end = 0;
  std::uint32_t own = 0, blended = 0;
  float blend_weight = 0.0f;
};

// The same layers, with each row's runs (runs[y], left to right, two neighbours never with the
// same values) in place of the per-pixel vectors, which are left empty: one pass over the depths,
// no per-pixel values written. Each pixel's values are those plan_depth_layers gives it. Throws
// as plan_depth_layers, and for a depth map that does not hold width_px x height_px values.
void plan_depth_layer_runs(const std::vector<float>& depth_m, int width_px, int height_px, const BlurGeometry& geometry,
                           const EyeErrorAtDistance& error, double tolerance_px, int threads, DepthLayerPlan& plan,
                           std::vector<std::vector<PixelRun>>& runs);

// The blur error between two power errors, in pixels (spectral norm of the difference times the
// geometry's pixels per dioptre).
double blur_error_px(const DioptricPower& first, const DioptricPower& second, const BlurGeometry& geometry);

}  // namespace glarelab
