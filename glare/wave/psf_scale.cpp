#include "glare/wave/psf_scale.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace glarelab {

std::vector<std::vector<PsfOverlap>> psf_overlap_weights(int input_px, double input_size, int output_px,
                                                         double output_size) {
  // Input pixel k spans [(k - N/2 - 1/2) a, (k - N/2 + 1/2) a]; output pixel m likewise with M, b.
  std::vector<std::vector<PsfOverlap>> weights(static_cast<std::size_t>(output_px));
  for (int k = 0; k < input_px; ++k) {
    const double lo = (k - input_px / 2 - 0.5) * input_size, hi = lo + input_size;
    const int m_first = std::max(0, static_cast<int>(std::floor(lo / output_size + output_px / 2 + 0.5)));
    const int m_last = std::min(output_px - 1, static_cast<int>(std::floor(hi / output_size + output_px / 2 + 0.5)));
    for (int m = m_first; m <= m_last; ++m) {
      const double out_lo = (m - output_px / 2 - 0.5) * output_size, out_hi = out_lo + output_size;
      const double overlap = std::min(hi, out_hi) - std::max(lo, out_lo);
      if (overlap > 0.0) weights[static_cast<std::size_t>(m)].push_back({k, overlap / input_size});
    }
  }
  return weights;
}

void check_psf_fits_display(int psf_size_px, double psf_degrees_per_pixel, double display_degrees_per_pixel) {
  const double a = psf_degrees_per_pixel, b = display_degrees_per_pixel;
  if (!(a > 0.0) || !(b > 0.0) || psf_size_px <= 0)
    throw PsfScaleError("glare/wave/psf_scale: PSF and display pixel sizes must be > 0 degrees");
  const double extent_display_px = psf_size_px * a / b;
  if (extent_display_px < 2.0) {
    std::ostringstream message;
    message << "glare/wave/psf_scale: the PSF spans " << psf_size_px * a << " deg = " << extent_display_px
            << " display pixels of " << b << " deg; fewer than 2, nothing to convolve with";
    throw PsfScaleError(message.str());
  }
  if (a > b) {
    std::ostringstream message;
    message << "glare/wave/psf_scale: PSF pixels (" << a << " deg) are coarser than display pixels (" << b
            << " deg); resampling would alias: compute the PSF over a wider aperture grid";
    throw PsfScaleError(message.str());
  }
}

int display_psf_size_px(int psf_size_px, double psf_degrees_per_pixel, double display_degrees_per_pixel) {
  const double extent_display_px = psf_size_px * psf_degrees_per_pixel / display_degrees_per_pixel;
  // Even output size covering the whole PSF extent, plus one pixel each side for the half-pixel
  // offsets between the two grids.
  int output_px = static_cast<int>(std::ceil(extent_display_px)) + 2;
  if (output_px % 2 != 0) ++output_px;
  return output_px;
}

Psf resample_psf_to_display(const Psf& psf, double display_degrees_per_pixel) {
  check_psf_fits_display(psf.size_px, psf.degrees_per_pixel, display_degrees_per_pixel);
  const double a = psf.degrees_per_pixel, b = display_degrees_per_pixel;
  const int output_px = display_psf_size_px(psf.size_px, a, b);
  const auto weights = psf_overlap_weights(psf.size_px, a, output_px, b);

  Psf out;
  out.size_px = output_px;
  out.degrees_per_pixel = b;
  out.channels = psf.channels;
  out.values.assign(static_cast<std::size_t>(psf.channels) * output_px * output_px, 0.0);
  const int n = psf.size_px;
  std::vector<double> rows_resampled(static_cast<std::size_t>(n) * output_px);  // n rows x M columns
  for (int c = 0; c < psf.channels; ++c) {
    for (int y = 0; y < n; ++y)
      for (int m = 0; m < output_px; ++m) {
        double sum = 0.0;
        for (const PsfOverlap& w : weights[static_cast<std::size_t>(m)]) sum += w.fraction * psf.at(c, w.input, y);
        rows_resampled[static_cast<std::size_t>(y) * output_px + m] = sum;
      }
    for (int my = 0; my < output_px; ++my)
      for (int mx = 0; mx < output_px; ++mx) {
        double sum = 0.0;
        for (const PsfOverlap& w : weights[static_cast<std::size_t>(my)])
          sum += w.fraction * rows_resampled[static_cast<std::size_t>(w.input) * output_px + mx];
        out.at(c, mx, my) = sum;
      }
  }
  return out;
}

}  // namespace glarelab
