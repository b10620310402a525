#pragma once
// Depth of field of the observer's eye over a scene with depth: each pixel blurred by the geometric
// blur of its own depth (Kakimoto et al. 2007: the blur field of Eqs. 8-9, section 4.4.2), drawn
// here per depth layer instead of per vertex.
//
// The stage: the scene's vergences are grouped into layers (stimuli/depth_layers.h: a new layer
// only where the blur changes by more than tolerance_px, 0.25 px by default; a pixel between two
// neighbouring layers' middles is shared between them); each layer, as premultiplied RGBA (colour
// times its pixels' coverage), is blurred by the uniform elliptical kernel of its middle vergence (stimuli/elliptical_kernel.h), directly or by FFT, whichever the
// cost model says is faster (stimuli/depth_of_field_blur.h); the blurred layers are added near to
// far, each through the transmission (1 - blurred coverage) of the nearer layers that hide it, and
// the sum is divided by the summed coverage; all of it a tile of frame rows at a time, so that a
// tile's pixels stay in the cache from its first layer to its last (stimuli/depth_of_field_tiles.h).
//
// Occlusion. A near surface at vergence v_n blocks part of the pupil for a point at v_f behind it
// when it lies within r = (v_n - v_f) r_p / (radians per pixel) pixels of that point (the far
// point's ray cone where it crosses the near surface's depth). The over operator (Porter and Duff
// 1984) lets the near layer's blurred coverage, of radius R_n (its own blur), stand for that
// blocking: exact when the far layer is in focus (then r = R_n), an overstatement when r is much
// smaller than R_n: two slices of one receding floor would each hide the other's light along their
// seam, though neither is in front of the other along any ray that reaches the pupil. So a layer
// hides the layers behind it only where r > max(R_n / 2, kOcclusionMinimumPx, the blending span
// of depth_layers.h); closer layers add, as slices of one surface do. The near layer is then composited "over" the far
// ones: a blurred near object spreads over the far one and hides what it covers.
//
// What layering cannot recover: the far surface hidden behind a near object's edge is not in the
// image, so where the blurred near edge turns semi-transparent there is nothing behind it to show.
// The far layer has a hole there, and dividing by the summed coverage fills that hole with the
// colours that are visible around it (the near edge's own colour inside the near object, the far
// colour outside). The per-pixel reference (stimuli/depth_of_field_reference.h) has no occlusion at
// all: every pixel spreads its own light, so far light also spreads over the near object. The two
// agree on each surface away from depth edges, at edges whose far side is sharp, and on surfaces
// whose depth changes smoothly; docs/DEPTH_OF_FIELD.md gives the measured difference.
//
// Image borders: light blurred past the frame is lost and no light comes in from outside it; the
// division by coverage renormalises the kernel there, so a uniform scene stays uniform up to the
// border.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/image.h"
#include "core/vector_isa.h"
#include "stimuli/depth_layers.h"
#include "stimuli/depth_of_field_rows.h"
#include "stimuli/depth_of_field_tiles.h"

namespace glarelab {

// Layers whose ray cones cross within this many pixels of each other do not hide one another:
// one pixel, the largest spacing of layers that blend at the default tolerance (4 x 0.25 px,
// depth_layers.h; at other tolerances that spacing is the floor), so neighbouring slices of a
// continuous surface always add.
inline constexpr double kOcclusionMinimumPx = 1.0;

struct DepthOfFieldSettings {
  double degrees_per_pixel = 0.0;     // visual angle of a pixel (display_model.h)
  double pupil_radius_m = 0.0;        // r_p of Kakimoto Eq. 8
  EyeErrorAtDistance residual_error;  // the eye's power error for each distance
  double tolerance_px = kDefaultLayerTolerancePx;
  int threads = 1;
  // The form of the direct blur's sums (depth_of_field_rows.h): SSE2, AVX2 or AVX-512 (the last two
  // by fused multiply-adds), each within the bound derived there of the others.
  VectorIsa vector_isa = widest_vector_isa_with_avx512();
};

struct DepthOfFieldReport {
  int layers = 0;                  // depth layers the scene needed
  int blurred_layers = 0;          // of them, those blurred (the rest passed through)
  int direct_layers = 0;           // blurred by direct convolution
  int fft_layers = 0;              // blurred by FFT
  double max_blur_error_px = 0.0;  // the largest blur error of any pixel's depth with its layer's
                                   // kernel alone (depth_layers.h; blending lowers it)
};

// image_cd_m2: linear RGB (cd/m2), alpha ignored and copied to the output with the depth map;
// depth_m: metres from the eye, one a pixel (stimuli/scene_depth.h: positive, +inf at infinity).
// Throws std::invalid_argument naming "stimuli/depth_of_field" for an empty image, non-finite or
// negative RGB, non-positive or non-finite degrees per pixel, pupil radius or tolerance, threads
// < 1 or a missing error function, and ImageError (stimuli/scene_depth) for a bad depth map.
// The result does not depend on `threads`. The pixels are checked as the stage's layers read them,
// so the kept-buffers form below may have written part of `result` when it refuses one.
ImageRGBA apply_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                               const DepthOfFieldSettings& settings, DepthOfFieldReport* report = nullptr);

// The stage's buffers, kept by a caller that blurs frame after frame (the whole-frame bench): the
// layer plan, each layer's row spans, the rows' stored stretches, each thread's tile buffers (the
// layers' rows, the transmission, the occluders' coverage), the rows and grids of layers blurred by
// FFT, reused instead of mapped afresh (page faults cost more than the blur itself at 1920 x 1080).
// A result does not depend on what they held before.
struct DepthOfFieldBuffers {
  DepthLayerPlan plan;
  std::vector<std::vector<PixelRun>> row_runs;
  std::vector<RowSpan> layer_spans;
  std::vector<RowSpan> written;  // each row's stretch of the sum stored this frame
  std::vector<DepthOfFieldTileBuffers> tiles;  // one a thread
  LayerRows rows;                              // a layer's rows for the FFT
  LayerFftBuffers fft;
  std::vector<BlurredLayerRows> fft_rows;      // the FFT's blurred layers, by plan index
  std::vector<std::pair<PixelBlurEllipse, EllipticalKernel>> kernels;  // the layers' kernels, by ellipse
};

// The same with kept buffers, into `result` (its memory reused when it already has the image's
// size; not the input image itself, refused as above); the same values as above.
void apply_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                          const DepthOfFieldSettings& settings, DepthOfFieldBuffers& buffers, ImageRGBA& result,
                          DepthOfFieldReport* report = nullptr);

// Checks shared with the per-pixel reference (the same refusals, the same messages).
void check_depth_of_field_inputs(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                 const DepthOfFieldSettings& settings);

}  // namespace glarelab
