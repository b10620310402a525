#pragma once
// Maps a PSF sampled at degrees_per_pixel onto the pixels of a display (DisplayModel::
// degrees_per_pixel_at_centre()), conserving each channel's sum. Resampling is by exact area
// overlap (box integration of the piecewise-constant PSF over each display pixel, separable in x
// and y): a pre-filter, so the finer PSF is averaged, never point-sampled, onto the display grid.
#include <stdexcept>
#include <vector>

#include "glare/wave/psf.h"

namespace glarelab {

class PsfScaleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Refuses (PsfScaleError naming both scales) when
//  - the PSF's whole extent (size_px * degrees_per_pixel) covers fewer than 2 display pixels: the
//    result would be a single pixel, no PSF left to convolve with;
//  - a PSF pixel is larger than a display pixel: the display would sample the PSF more finely than
//    it was computed, and any interpolation would invent (alias) structure between its samples.
//    Compute the PSF over a wider aperture grid instead (degrees_per_pixel = lambda / width).
// The output is square, even-sized, centred on (size/2, size/2) like every Psf.
Psf resample_psf_to_display(const Psf& psf, double display_degrees_per_pixel);

// The refusals of resample_psf_to_display for a PSF of psf_size_px pixels of psf_degrees_per_pixel,
// without a PSF: so a session can find, before it writes anything, that its glare cannot be shown
// at its display's scale. Throws PsfScaleError.
void check_psf_fits_display(int psf_size_px, double psf_degrees_per_pixel, double display_degrees_per_pixel);

// The size (even) of resample_psf_to_display's output for a PSF of psf_size_px pixels.
int display_psf_size_px(int psf_size_px, double psf_degrees_per_pixel, double display_degrees_per_pixel);

// The 1D box-overlap weights resample_psf_to_display applies along x and then y: weights[m] lists
// (input pixel k, fraction of input pixel k inside output pixel m), both grids centred on size/2.
// glare/cpu/float_spectral_psf.h folds them into its wavelength scaling.
struct PsfOverlap {
  int input;
  double fraction;
};
std::vector<std::vector<PsfOverlap>> psf_overlap_weights(int input_px, double input_size, int output_px,
                                                         double output_size);

}  // namespace glarelab
