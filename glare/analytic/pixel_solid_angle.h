#pragma once
// The solid angle each pixel of a flat frame subtends at the eye, relative to the pixel on the line
// of sight (the frame's centre): w = Omega(x, y) / Omega(0, 0) = cos^3 theta = (d^2 / (d^2 + x^2 +
// y^2))^(3/2), x and y in mm from the centre, d the viewing distance (dOmega = d dA / r^3).
//
// Why the glare needs it: a display kernel (glare/analytic/display_glare_kernel.h) holds the PSF's
// energy per pixel for a source on the line of sight, and a frame holds luminance. A pixel's
// luminance is its energy over its own solid angle, so the glare of a frame L is
//     L_glare(p) = (1 / w(p)) sum_q w(q) L(q) K(p - q),
// the shift-invariant kernel carrying light between pixels as energies. For a source on the line of
// sight this is E x PSF(theta) at every pixel (E the source's illuminance at the eye); without the
// weights the veil would be cos^3 theta low there (17 % at 20 degrees). A source's own pixel keeps
// its luminance (w(p) = w(q)), and the frame's energy, sum w L, is what the kernel keeps.
#include <vector>

#include "core/image.h"
#include "glare/analytic/display_glare_kernel.h"

namespace glarelab {

class PixelSolidAngle {
 public:
  PixelSolidAngle(const DisplayGeometry& geometry, int width_px, int height_px);

  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  // Omega(x, y) / Omega at the line of sight, from the pixel's centre.
  float relative(int x, int y) const { return relative_[static_cast<std::size_t>(y) * width_px_ + x]; }

  // Luminance to energy per pixel (in units of the axial pixel's solid angle): RGB times w; alpha kept.
  ImageRGBA to_energy(const ImageRGBA& luminance) const;
  // Energy per pixel back to luminance, in place: RGB over w.
  void to_luminance(ImageRGBA& energy) const;

 private:
  int width_px_ = 0, height_px_ = 0;
  std::vector<float> relative_;
};

}  // namespace glarelab
