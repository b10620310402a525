#pragma once
// Convolution of an HDR image with a PSF by FFT on the CPU (FFTW), per channel. The image and the
// PSF are zero padded to at least (H + M - 1) x (W + M - 1) (then up to a 2,3,5,7-smooth size), so
// the circular convolution equals the linear one: nothing wraps around the image edge, and any image
// size works. The PSF must already be at the image's pixel scale (glare/wave/psf_scale.h).
//
// A very bright source (a 1e8 cd/m2 sun) next to a dim background makes the FFT's rounding noise,
// about eps * (the bright energy), spread over the whole image; in float32 that swamps a 1e-2 cd/m2
// background. `bright_threshold` splits the image: pixels above it are convolved by direct summation
// of shifted PSF copies in double (exact, costs bright_pixels * M^2), the rest by FFT.
#include <vector>

#include "glare/cpu/fft.h"
#include "glare/wave/psf.h"
#include "core/image.h"

namespace glarelab {

struct ConvolutionOptions {
  FftPrecision precision = FftPrecision::float64;
  double bright_threshold = 0.0;  // > 0: pixels above it are summed directly (see above); 0: off
};

struct ConvolutionReport {
  std::size_t bright_pixels = 0;  // per channel, summed over channels
  int fft_rows = 0, fft_cols = 0;
};

// One plane (width x height, row-major) with one PSF channel; double in and out.
std::vector<double> convolve_plane_cpu(const std::vector<double>& plane, int width_px, int height_px, const Psf& psf,
                                       int psf_channel, const ConvolutionOptions& options,
                                       ConvolutionReport* report = nullptr);

// R, G, B of the image each with the PSF's channel of the same index (a one-channel PSF serves all
// three); alpha and depth are copied unchanged. Refuses (std::invalid_argument naming the pixel
// counts) an image with NaN, Inf or negative R, G, B.
ImageRGBA convolve_image_cpu(const ImageRGBA& image, const Psf& psf, const ConvolutionOptions& options,
                             ConvolutionReport* report = nullptr);

// The same after mapping the PSF onto the image's pixel scale (glare/wave/psf_scale.h: sum-conserving,
// throws PsfScaleError when it cannot).
ImageRGBA convolve_image_at_scale_cpu(const ImageRGBA& image, double image_degrees_per_pixel, const Psf& psf,
                                      const ConvolutionOptions& options, ConvolutionReport* report = nullptr);

}  // namespace glarelab
