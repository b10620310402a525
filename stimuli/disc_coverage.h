#pragma once
// Antialiased discs by exact pixel-area coverage: the fraction of each pixel's unit square that
// lies inside a circle, integrated in closed form (no supersampling), so a disc of area pi r^2
// puts exactly pi r^2 pixel areas of light into an image whatever its size or position. The
// comparison stimulus of Spencer et al. 1995, section 4 (a "hardware-drawn disc surrounded by an
// annulus") and the light source of its glare images are drawn with it (stimuli/spencer_scenes.h).
namespace glarelab {

// Area of the intersection of the disc of radius `radius_px` centred at (cx, cy) with the
// axis-aligned rectangle [x0, x1] x [y0, y1] (all in pixel units). 0 for an empty rectangle or a
// radius <= 0.
double disc_rectangle_overlap(double cx, double cy, double radius_px, double x0, double y0, double x1, double y1);

// Coverage of pixel (x, y), whose square is [x, x + 1] x [y, y + 1], by that disc: in [0, 1].
inline double disc_pixel_coverage(double cx, double cy, double radius_px, int x, int y) {
  return disc_rectangle_overlap(cx, cy, radius_px, x, y, x + 1.0, y + 1.0);
}

}  // namespace glarelab
