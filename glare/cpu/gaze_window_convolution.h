#pragma once
// Gaze-contingent glare (Luidolt 2020, sections 5.2.3 and 6.3.3): the PSF convolution is computed
// only in a square, power-of-two window around the gaze point and blended into the rest of the
// image with a Gaussian falloff, so the glare is strongest where the participant looks and the FFT
// is smaller than the frame's.
//
// Exactness: the window is convolved together with an apron of image pixels around it. With the
// default apron (the PSF's reach, M/2 pixels for an M x M PSF centred on (M/2, M/2)) every source
// that the full-frame convolution sums into a window pixel is inside the convolved area, so the
// window equals the full-frame convolution (glare/cpu/convolution.h) to FFT rounding. A smaller apron
// a saves work and is exact at least (M/2 - a) pixels inside the window's border.
//
// Blend (Luidolt 6.3.3: "blends the original (unconvolved) image with the bloomed window using a
// Gaussian falloff"): out = base + w (windowed - base), w(x, y) = exp(-d^2 / (2 sigma^2)) with d
// the distance of the pixel centre from the gaze point, inside the window; w = 0 outside it.
// Luidolt gives no sigma; the default, window side / 6, puts the window edge 3 sigma from a
// centred gaze point, so the step left at the edge is at most exp(-4.5) = 1.1% of the glare.
#include <vector>

#include "glare/cpu/convolution.h"
#include "glare/wave/psf.h"
#include "core/image.h"

namespace glarelab {

struct GazeWindowOptions {
  int window_px = 512;            // window side, a power of two
  double falloff_sigma_px = 0.0;  // Gaussian sigma of the blend weight; 0: window_px / 6
  int apron_px = -1;              // image pixels convolved around the window; -1: the PSF's reach (exact)
  ConvolutionOptions convolution;
};

// Where the window lies for one frame. Gaze in normalised display coordinates (0..1, origin at the
// top left, y down: docs/TRACKERS.md); the window is centred on it and shifted to stay inside the
// image (a gaze at a corner gives a window in that corner, the falloff still centred on the gaze).
struct GazeWindow {
  int x0_px = 0, y0_px = 0;            // top-left pixel of the window
  int width_px = 0, height_px = 0;     // window_px, or the image size when that is smaller
  double gaze_x_px = 0.0, gaze_y_px = 0.0;  // gaze in pixel coordinates (pixel x spans [x, x + 1))
  double sigma_px = 0.0;
  int apron_px = 0;
  bool contains(int x, int y) const { return x >= x0_px && x < x0_px + width_px && y >= y0_px && y < y0_px + height_px; }
};

// Throws std::invalid_argument (naming glare/gaze_window) for a window side that is not a power of
// two, a non-finite gaze, a negative sigma or an empty image or PSF.
GazeWindow place_gaze_window(int image_width_px, int image_height_px, double gaze_x, double gaze_y, int psf_size_px,
                             const GazeWindowOptions& options);

// The blend weight w(x, y) of pixel (x, y) (see above).
double gaze_blend_weight(const GazeWindow& window, int x, int y);

// The convolution of `plane` (width x height, row-major) restricted to the window: width_px x
// height_px values, row-major from (x0, y0).
std::vector<double> convolve_gaze_window_plane(const std::vector<double>& plane, int width_px, int height_px,
                                               const Psf& psf, int psf_channel, const GazeWindow& window,
                                               const ConvolutionOptions& options, ConvolutionReport* report = nullptr);

// The full frame: `base` (the unconvolved plane, or a cheaper glare of it) with the windowed
// convolution blended in.
std::vector<double> blend_gaze_window_plane(const std::vector<double>& base, int width_px, int height_px,
                                            const std::vector<double>& windowed, const GazeWindow& window);

// base with glared blended in over the window (R, G, B; alpha and depth base's): for a kernel that
// reaches every pixel (the analytic, hybrid and human eyes) the window's exact apron is the whole
// frame, so the whole frame's glare is the window's.
ImageRGBA blend_gaze_window(const ImageRGBA& base, const ImageRGBA& glared, const GazeWindow& window);

// R, G, B each convolved in the window with the PSF channel of the same index (one-channel PSF:
// all three) and blended into the unconvolved image; alpha and depth copied. The PSF must be at
// the image's pixel scale (glare/wave/psf_scale.h). Refuses images with NaN, Inf or negative R, G, B.
ImageRGBA convolve_image_gaze_window_cpu(const ImageRGBA& image, const Psf& psf, double gaze_x, double gaze_y,
                                         const GazeWindowOptions& options, ConvolutionReport* report = nullptr);

}  // namespace glarelab
