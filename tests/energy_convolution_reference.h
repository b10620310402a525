#pragma once
// Float64 references for the glare stage's analytic frames. The glare of a frame as the stage reads
// a display kernel (energy per pixel, glare/analytic/pixel_solid_angle.h), computed here from the
// display's geometry: each pixel's luminance times its solid angle over the centre pixel's (cos^3
// of its angle off the line of sight through the frame's centre) in, the kernel's float64
// convolution, the same division out.
#include <algorithm>
#include <cmath>

#include "core/display_spec.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/wave/psf.h"

namespace glarelab::test {

// A hybrid eye's whole kernel built by hand: the achromatic far kernel copied to R, G and B, the
// near PSF (odd size, centred on the source) added around the centre.
inline DisplayKernel far_plus_near_kernel(DisplayKernel whole, const Psf& near) {
  whole.channels = 3;
  whole.values.resize(3 * whole.values.size(), 0.0);
  const std::size_t plane = static_cast<std::size_t>(whole.width_px()) * whole.height_px();
  for (int c = 1; c < 3; ++c) std::copy_n(whole.values.begin(), plane, whole.values.begin() + c * plane);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < near.size_px; ++y)
      for (int x = 0; x < near.size_px; ++x) whole.at(c, x - near.size_px / 2, y - near.size_px / 2) += near.at(c, x, y);
  return whole;
}

inline double relative_pixel_solid_angle(const DisplaySpec& display, int width_px, int height_px, int x, int y) {
  const double x_mm = (x + 0.5 - 0.5 * width_px) * display.pixel_pitch_mm;
  const double y_mm = (y + 0.5 - 0.5 * height_px) * display.pixel_pitch_mm;
  const double d = display.viewing_distance_mm;
  return std::pow(d / std::sqrt(d * d + x_mm * x_mm + y_mm * y_mm), 3.0);
}

inline ImageRGBA convolve_as_energy_float64(const ImageRGBA& frame, const DisplayKernel& kernel, const DisplaySpec& display) {
  ImageRGBA energy = frame;
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x)
      for (int c = 0; c < 3; ++c)
        energy.pixel(x, y)[c] = static_cast<float>(
            frame.pixel(x, y)[c] * relative_pixel_solid_angle(display, frame.width_px, frame.height_px, x, y));
  ImageRGBA glare = convolve_with_kernel_float64(energy, kernel);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x)
      for (int c = 0; c < 3; ++c)
        glare.pixel(x, y)[c] = static_cast<float>(
            glare.pixel(x, y)[c] / relative_pixel_solid_angle(display, frame.width_px, frame.height_px, x, y));
  return glare;
}

}  // namespace glarelab::test
