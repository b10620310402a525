#pragma once
// An analytic PSF (glare/analytic/analytic_psf.h) on the pixels of a flat display: the kernel K(dx, dy) is the
// PSF's energy falling on the display pixel dx, dy pixels from the source pixel, that is the PSF
// integrated over that pixel's solid angle. The source sits on the line of sight (the display
// centre, where the participant fixates), the display is a plane at viewing_distance_mm with
// square pixels of pixel_pitch_mm; a pixel at (x, y) mm from the foot of the line of sight lies
// theta = atan(|(x, y)| / d) from it and subtends dOmega = d / (d^2 + x^2 + y^2)^(3/2) dx dy, so
// off-axis pixels are smaller in angle. Using this kernel for every source pixel (a convolution)
// takes the glare as shift-invariant on the display; for sources off the line of sight that is
// exact in angle to first order (the pixel's angular size changes by cos^3, 1 % at 5 degrees).
//
// The integral over each pixel (pixel_energy): pixels near the source in polar coordinates about
// it, the angle split at the pixel's corners and the radius at the profile's scale changes (the
// f0 core, the 0.02 degree knee of f1/f2, CIE's 0.1 degree kink), Gauss-Legendre in both; farther
// pixels by a tensor Gauss-Legendre rule whose order follows the profile's local scale in pixels
// (pixels subdivided where it is under 5 pixels, e.g. the halo on a coarse display). Relative
// accuracy about 1e-7 per pixel (tests/glare_display_kernel_test.cpp checks 1e-5 against
// adaptive Gauss-Kronrod).
#include <vector>

#include "glare/analytic/analytic_psf.h"

namespace glarelab {

struct DisplayGeometry {
  double viewing_distance_mm = 600.0;
  double pixel_pitch_mm = 0.25;
};

struct DisplayKernel {
  int half_width_px = 0;   // offsets -half_width..half_width
  int half_height_px = 0;
  int channels = 1;        // 1 (achromatic) or 3 (R, G, B)
  std::vector<double> values;  // channel-major rows: [c][dy + half_height][dx + half_width]

  int width_px() const { return 2 * half_width_px + 1; }
  int height_px() const { return 2 * half_height_px + 1; }
  double at(int channel, int dx, int dy) const {
    return values[(static_cast<std::size_t>(channel) * height_px() + (dy + half_height_px)) * width_px() +
                  (dx + half_width_px)];
  }
  double& at(int channel, int dx, int dy) {
    return values[(static_cast<std::size_t>(channel) * height_px() + (dy + half_height_px)) * width_px() +
                  (dx + half_width_px)];
  }
  double energy(int channel) const;  // sum of the channel
};

// The energy of `channel` on the pixel (dx, dy) pixels from the source pixel (without the CIE peak).
double pixel_energy(const AnalyticPsf& psf, int channel, int dx, int dy, const DisplayGeometry& geometry);

// The kernel over offsets up to half_width x half_height pixels, the CIE peak added to the centre.
// A frame of W x H pixels needs half sizes W - 1 and H - 1 for every pixel to reach every other.
// `threads` splits the rows (the result does not depend on it).
DisplayKernel analytic_display_kernel(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                      int half_height_px, int threads = 2);

// The fraction of each channel's PSF energy that lands on a display of width x height pixels
// around the source (the rest falls beyond its edges): independent of the kernel, by integrating
// the radial energy up to each direction's edge (1D quadrature over the direction), for checking
// the kernel's sum.
double energy_within_rectangle(const AnalyticPsf& psf, int channel, const DisplayGeometry& geometry,
                               double half_width_mm, double half_height_mm);

}  // namespace glarelab
