#pragma once
// The geometric blur of a dioptric power error drawn on the image's pixel grid: a uniform
// ellipse (Kakimoto et al. 2007, Eq. 8: the pupil disc mapped by the error, section of Sturm's
// conoid), antialiased by supersampled pixel coverage and normalised to unit sum.
//
// Frames: glare/refraction/dioptric_power.h gives the ellipse in the observer frame (x right, y UP); image
// rows run DOWN, so a direction at angle phi in the observer frame is drawn at -phi on the image
// (the y component changes sign). The scale from the visual field to the image is Kakimoto's s_h
// and s_v of Eq. 9, here 1 / radians_per_pixel in both directions (square pixels, small angles).
#include <vector>

#include "glare/refraction/dioptric_power.h"

namespace glarelab {

// The blur ellipse of `error` on the image: semi-axes in pixels, major axis in the observer frame.
struct PixelBlurEllipse {
  double semi_major_px = 0.0;
  double semi_minor_px = 0.0;
  double major_axis_angle_deg = 0.0;  // from +x, counterclockwise with y UP (observer frame), [0, 180)
};

// pupil_radius_m > 0 and degrees_per_pixel > 0 (checked by the caller): semi-axes
// |lambda_i| r_p (radians, geometric_blur_ellipse) divided by the radians a pixel subtends.
PixelBlurEllipse pixel_blur_ellipse(const DioptricPower& error, double pupil_radius_m, double degrees_per_pixel);

// Subsamples per pixel side of the coverage estimate: 16 x 16 = 256 a pixel puts a straight edge's
// coverage within 1/32 of a pixel area, and the kernel then grows with the ellipse in steps of
// 1/256 px^2, fine enough for the blend of two layers' kernels (depth_layers.h) to follow the
// kernel in between: with 8 x 8 the ramp of tests/stimuli_depth_of_field_test.cpp was 1.55% off
// the per-pixel reference instead of 1.21%.
inline constexpr int kKernelSubsamplesPerAxis = 16;

// A normalised kernel of (2 radius_y + 1) rows of (2 radius_x + 1) taps; tap (dx, dy) is the light
// a point at the kernel's centre sends to the pixel dx to the right and dy DOWN.
struct EllipticalKernel {
  int radius_x_px = 0;
  int radius_y_px = 0;
  std::vector<double> weights;    // row-major, row 0 is dy = -radius_y_px (the top); sums to 1
  double covered_area_px2 = 0.0;  // coverage summed before normalising: pi a b for a resolved ellipse
  int width() const { return 2 * radius_x_px + 1; }
  int height() const { return 2 * radius_y_px + 1; }
  double at(int dx, int dy) const {
    return weights[static_cast<std::size_t>((dy + radius_y_px) * width() + dx + radius_x_px)];
  }
  int nonzero_taps() const;
};

// Each tap is the fraction of its pixel square [dx - 1/2, dx + 1/2] x [dy - 1/2, dy + 1/2] inside
// the ellipse centred at the origin, estimated on a regular subsamples x subsamples grid. A
// semi-axis below one subsample spacing (1 / subsamples px: a line focus, or a point in focus) is
// widened to it so that the ellipse still contains subsamples; its light then stays on the line
// (or in the centre pixel) it belongs to. An ellipse within the centre pixel is the identity kernel.
EllipticalKernel elliptical_kernel(const PixelBlurEllipse& ellipse, int subsamples_per_axis = kKernelSubsamplesPerAxis);

}  // namespace glarelab
