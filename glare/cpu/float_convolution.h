#pragma once
// The RGB convolution of glare/cpu/convolution.h in float32 for a stream of frames of one size, zero padded
// to a 2,3,5-smooth size at which the circular convolution's wanted values are the linear
// convolution's (image + M - 1 for `full` output, image + M/2 for `same`; the constructor says why):
// FFTW plans (measured once per machine and kept, glare/cpu/fftw_wisdom.h) and buffers made once, the three
// channels transformed by one plan each way, on kGlareCpuThreads threads. The scene's spectrum is
// kept: a static scene (the same image frame after frame, a new PSF each frame) costs 3 forward +
// 3 inverse transforms, a new scene 3 more.
// Each 2D transform is a row pass and a column pass of 1D FFTW transforms, so that the row pass
// skips the rows that are zero padding (forward: all rows below the image, below the PSF, which is
// only M of its rows x cols) or not wanted (inverse: all rows outside the output's). The spectra are
// kept transposed (glare/cpu/fftw_float_plan.h), so the column pass runs in place over contiguous columns; the
// forward row pass transforms each row as it is copied in (forward_rows).
//
// Two outputs: `same` (the image's own size, the PSF centred: convolve_image_cpu's result) and
// `full` (the whole linear convolution, image + M - 1 each way, for a region of a larger frame whose
// glare spills past it: write_full). Several scenes of one size can be kept at once (slots: the
// separate lit regions of one frame), all convolved with one transform of the frame's PSF.
// Checked against convolve_image_cpu in float64 (tests/glare_cpu_float_test.cpp).
#include <complex>
#include <functional>
#include <vector>

#include "core/image.h"
#include "glare/cpu/fftw_float_plan.h"
#include "glare/wave/psf.h"

namespace glarelab {

enum class ConvolutionOutput { same, full };
// How write_full puts the convolution into the frame: over its R, G, B, or added to them.
enum class FullWrite { replace, add };

// A pass over the pixels a convolution writes, done while they are in cache: called with (y,
// x_from, x_to, the RGBA of pixel (x_from, y)) for each row segment written, from the
// convolution's threads (it must touch only those pixels).
using RowFinish = std::function<void(int y, int x_from, int x_to, float* rgba)>;

class CpuFloatConvolution {
 public:
  // Frames of width x height pixels with PSFs of kernel_px x kernel_px (display scale), with room
  // for `slots` scenes.
  CpuFloatConvolution(int width_px, int height_px, int kernel_px, int threads = kGlareCpuThreads,
                      ConvolutionOutput output = ConvolutionOutput::same, int slots = 1);
  int fft_rows() const { return rows_; }
  int fft_cols() const { return cols_; }
  int slots() const { return slots_; }

  // A new scene: its R, G, B forward transforms, kept for every convolve() until the next one.
  // Refuses (std::invalid_argument) a wrong size and NaN, Inf or negative R, G, B, as convolve_image_cpu.
  void set_scene(const ImageRGBA& image, int slot = 0);
  // The same for the width x height pixels of `frame` from (x0, y0) on (a region of a larger frame).
  void set_scene(const ImageRGBA& frame, int x0, int y0, int slot);
  // The scene convolved with `psf` (1 or 3 channels, kernel_px wide) into `out` (resized once);
  // alpha and depth copied from the scene. `same` output only.
  void convolve(const Psf& psf, ImageRGBA& out);

  // The PSF's spectrum for the write_full() calls that follow (one per frame, shared by the slots).
  void set_kernel(const Psf& psf);
  // `full` output: the slot's scene, placed in `frame` at (x0, y0), convolved with the set_kernel()
  // PSF; the whole linear convolution (the scene grown by the PSF's reach, M/2 before, M - 1 - M/2
  // after) written over R, G, B of `frame` there (FullWrite::add: added to them), clipped to the
  // frame; alpha untouched. `finish`, when given, is called on each row segment once it is written.
  void write_full(int slot, ImageRGBA& frame, int x0, int y0, const RowFinish* finish = nullptr,
                  FullWrite write = FullWrite::replace);

 private:
  int width_ = 0, height_ = 0, kernel_px_ = 0, rows_ = 0, cols_ = 0, threads_ = 1, slots_ = 1;
  ConvolutionOutput output_ = ConvolutionOutput::same;
  std::vector<bool> has_scene_;
  bool has_kernel_ = false;
  std::vector<float> scene_alpha_, scene_depth_;  // `same`: the last scene's alpha and depth
  std::vector<float> incoming_alpha_;              // a new scene's alpha while it is checked
  FftwFloatBuffer<std::complex<float>> kernel_spectrum_, product_;
  // Each slot's scene spectrum, and the one a new scene is transformed into: swapped with the slot's
  // once the scene is accepted, so that a refused scene leaves the last one's.
  std::vector<FftwFloatBuffer<std::complex<float>>> scene_spectra_;
  FftwFloatBuffer<std::complex<float>> incoming_spectrum_;
  const std::complex<float>* spectrum(int slot) const { return scene_spectra_[static_cast<std::size_t>(slot)].data(); }
  // The forward row pass, fused with the copy in: kRowTile rows at a time per thread, each row copied
  // into a thread's row buffer (R, G, B) and transformed while in cache (real_row_forward), the
  // tile's spectra then written transposed, kRowTile consecutive values of each column at once.
  static constexpr int kRowTile = 8;
  struct RowScratch {
    FftwFloatBuffer<float> rows;                  // R, G, B: 3 x row_stride_ (zero past what was written)
    FftwFloatBuffer<std::complex<float>> tile;    // 3 x kRowTile x tile_stride_
    int written_width = 0;                        // values of each row the last fill wrote
  };
  int row_stride_ = 0, tile_stride_ = 0;  // cols_ and cols_/2 + 1 rounded up to 64 bytes
  std::vector<RowScratch> row_scratch_;   // one per thread (parallel_indexed_chunks' chunk)
  // Channel c's row buffer, and channel c's row r of the tile.
  float* scratch_row(RowScratch& scratch, int c) const {
    return scratch.rows.data() + static_cast<std::size_t>(c) * static_cast<std::size_t>(row_stride_);
  }
  std::complex<float>* tile_row(RowScratch& scratch, int c, int r) const {
    return scratch.tile.data() + (static_cast<std::size_t>(c) * kRowTile + static_cast<std::size_t>(r)) * static_cast<std::size_t>(tile_stride_);
  }
  FftwFloatPlan row_forward_, row_inverse_;
  // Rows [0, row_count) of the three channels of `spectrum` (transposed), filled by
  // fill(y, r, g, b), which writes `width` values of row y into each and returns false for values
  // the convolution refuses; the rows are transformed either way. Returns whether all were accepted.
  template <typename Fill>
  bool forward_rows(int row_count, int width, std::complex<float>* spectrum, const Fill& fill);
  // The inverse row pass, fused with the copy out: rows [first_row, first_row + row_count) of the
  // three channels of `product` (transposed; destroyed), kRowTile at a time per thread, read into a
  // thread's tile, transformed row by row (real_row_inverse) and handed to emit(row, r, g, b)
  // while in cache.
  template <typename Emit>
  void inverse_rows(std::complex<float>* product, int first_row, int row_count, const Emit& emit);
  // Clears rows [first_row, rows) of the three spectra in `spectrum` (the row pass leaves there
  // what the in-place column pass of the last frame wrote).
  void clear_rows(std::complex<float>* spectrum, int first_row) const;
  // The R, G, B of width x height pixels from (x0, y0) of `image` into slot `slot`'s spectrum.
  void transform_scene(const ImageRGBA& image, int x0, int y0, int slot);
  // kernel spectrum x slot spectrum / (rows cols) into product_ (`full`; `same`: into the kernel
  // spectrum itself), then the inverse's column pass; returns the product.
  std::complex<float>* multiply_and_invert_columns(int slot);
  FftwFloatPlan image_column_pass_, kernel_column_pass_, inverse_column_pass_;
};

}  // namespace glarelab
