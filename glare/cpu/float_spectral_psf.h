#pragma once
// The spectral PSF of glare/wave/spectral_psf.h (Ritschel et al. 2009, section 5: n wavelengths, each the
// reference PSF scaled by lambda_ref / lambda with bilinear interpolation and the Jacobian, weighted
// by the CIE CMFs in linear Rec.709), computed straight at the display's pixel scale in float32 for
// the convolution, instead of on the N x N grid and then box-resampled (glare/wave/psf_scale.h).
//
// Why it is the same operator: the bilinear scaling B_i and the box resampling R are both separable
// and linear, so R (B_i F B_i^T) R^T = W_i F W_i^T with W_i = R B_i, an M x N band matrix (M display
// pixels) precomputed once per wavelength; F is read once per wavelength band, and only M x M
// values are accumulated per wavelength instead of N x N. The one non-linear step, clamping
// negative Rec.709 values (spectral colours outside the gamut) to 0 on PSF pixels, is redone on the
// PSF pixels of the display pixels where a channel may change sign (compute()); elsewhere the box
// mean is clamped. `glarelab bench` reports the frame error against the float64 path.
#include <vector>

#include "glare/wave/psf.h"
#include "glare/wave/psf_scale.h"

namespace glarelab {

struct CpuFloatSpectralSettings {
  int grid_px = 512;                    // N of the reference PSF
  double psf_degrees_per_pixel = 0.0;   // of the reference PSF
  double display_degrees_per_pixel = 0.0;
  int wavelength_samples = 32;
  double reference_wavelength_nm = 575.0;
  double aperture_width_mm = 10.0;     // of the pupil-plane grid the reference PSF came from
  int threads = 2;
};

class CpuFloatSpectralPsf {
 public:
  // Row m of a wavelength's W (display pixel m from reference pixels): count weights from `first`.
  struct Band {
    int first = 0;   // first reference pixel
    int count = 0;   // weights
    int offset = 0;  // into weights_
  };
  // Throws PsfScaleError when the PSF cannot be shown at the display's scale (glare/wave/psf_scale.h).
  explicit CpuFloatSpectralPsf(const CpuFloatSpectralSettings& settings);
  int display_size_px() const { return display_px_; }
  // `power`: the N x N reference PSF (any positive scale; each channel is normalised to sum 1),
  // column-major as CpuFloatPsf::power_column_major() holds it: pixel (x, y) at [x N + y].
  // Returns R, G, B at the display scale, as resample_psf_to_display(spectral_psf_from_reference()).
  // pupil_diameter_mm: the aperture's pupil, for the size of the PSF's core (compute()).
  Psf compute(const float* power, double pupil_diameter_mm);
  // Display pixels of the last compute() whose clamp was done on PSF pixels (see compute()).
  int refined_pixels() const { return refined_pixels_; }

 private:
  struct Wavelength {
    double rgb_weight[3];     // Jacobian times the CMF weight in linear Rec.709
    float rgb_weight_float[3];  // the same in float, for the refinement's PSF pixels
    bool compact = true;      // interpolate_along_row's vector form applies (the constructor)
    // Per PSF pixel x: the two bilinear neighbours of the scaled position and their weights, a
    // neighbour outside the grid clamped onto it with weight 0 (it reads 0 in glare/wave/spectral_psf.cpp).
    std::vector<int> index0, index1;
    std::vector<float> weight0, weight1;
    std::vector<Band> bands;  // one per display pixel (row or column, the matrix is square)
    int first_column = 0, last_column = -1;  // reference columns any band reads
  };
  // A thread's buffers for a tile of display rows (compute()).
  struct TileScratch {
    std::vector<float> row;     // kTile rows of W_i F: kTile x N
    std::vector<float> tile_t;  // the same transposed: N x kTile
    std::vector<float> tile_d;  // W_i F W_i^T of the kTile display rows, M x kTile, per wavelength
  };
  // A run of refined display pixels [first_display, end_display) along a display row, and its PSF
  // columns [first_column, first_column + columns) at `offset` in the row's block.
  struct BlockSegment {
    int first_column = 0, columns = 0, offset = 0;
    int first_display = 0, end_display = 0;
  };
  // R, G, B of the N x N spectral PSF, as glare/wave/spectral_psf.cpp computes them (in float), on the PSF
  // pixels of the segments' columns x ys (the PSF rows of one display row): rgb[(c |ys| + j) width_px
  // + segment.offset + i], each channel's rows contiguous so that the loops along them vectorise.
  void spectral_block(const float* power, const std::vector<BlockSegment>& segments, int width_px,
                      const std::vector<PsfOverlap>& ys, std::vector<float>& rgb) const;
  // compute()'s steps: W_i F W_i^T of every wavelength summed into totals_, the screen that marks
  // straddles_, and the marked display pixels summed again from their PSF pixels, clamped.
  void add_spectral_tiles(const float* power);
  void screen_straddles(double pupil_diameter_mm);
  void refine_straddles(const float* power);
  // Rows of W_i F made at a time, then transposed so that the pass along them (W_i F W_i^T) takes a
  // vector of kTile rows a step (compute()).
  static constexpr int kTile = 8;
  CpuFloatSpectralSettings settings_;
  int display_px_ = 0;
  std::vector<Wavelength> wavelengths_;
  std::vector<float> weights_;
  std::vector<int> active_;          // wavelengths whose bands read any reference pixel
  std::vector<double> sum_weights_;  // per sum p (R, |R|, G, |G|, B, |B|) and active wavelength s: p |active_| + s
  std::vector<TileScratch> scratch_;  // one per thread (parallel_indexed_chunks' chunk)
  std::vector<double> totals_;       // 6 x M x M, transposed: R, G, B, then the sums of their magnitudes
  std::vector<std::vector<PsfOverlap>> box_;  // glare/wave/psf_scale.h's weights, PSF to display
  std::vector<unsigned char> straddles_;      // per display pixel: refined on PSF pixels
  // The screen's sign bits (bit c: channel c negative), and their OR and AND along y (compute()).
  std::vector<unsigned char> negative_, along_y_any_, along_y_all_;
  int refined_pixels_ = 0;
};

}  // namespace glarelab
