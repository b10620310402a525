#include "glare/cpu/float_convolution.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

#include "core/fft_size.h"
#include "core/parallel_for.h"
#include "glare/cpu/complex_transpose.h"
#include "glare/cpu/rgba_rows.h"

namespace glarelab {

CpuFloatConvolution::CpuFloatConvolution(int width_px, int height_px, int kernel_px, int threads,
                                         ConvolutionOutput output, int slots)
    : width_(width_px),
      height_(height_px),
      kernel_px_(kernel_px),
      threads_(std::max(1, threads)),
      slots_(slots),
      output_(output) {
  if (width_px <= 0 || height_px <= 0 || kernel_px <= 0)
    throw std::invalid_argument("glare/cpu/float_convolution: image and PSF sizes must be > 0");
  if (slots < 1) throw std::invalid_argument("glare/cpu/float_convolution: at least one scene slot");
  // Padding. `full` keeps the whole linear convolution, image + M - 1 values each way. `same` keeps
  // only the image's values, full indices [M/2, M/2 + size): the circular convolution of length L
  // folds full index j >= L onto j - L, and the last one, size + M - 2, folds below M/2 when
  // L >= size + M/2, which also holds the last value read (M/2 + size - 1). The PSF needs L >= M.
  const auto padded = [&](int size) {
    const int needed = output == ConvolutionOutput::full ? size + kernel_px - 1 : std::max(size + kernel_px / 2, kernel_px);
    return smooth_fft_size(needed);
  };
  rows_ = padded(height_px);
  cols_ = padded(width_px);
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * (cols_ / 2 + 1);
  kernel_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  // `same` (one PSF per scene): the product overwrites the PSF's spectrum in place, as the inverse
  // destroys its input anyway; `full` keeps the PSF's spectrum for the next slot.
  if (output == ConvolutionOutput::full) product_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  std::complex<float>* product = output == ConvolutionOutput::full ? product_.data() : kernel_spectrum_.data();
  for (int k = 0; k < slots; ++k) scene_spectra_.emplace_back(3 * spectrum_size);
  incoming_spectrum_ = FftwFloatBuffer<std::complex<float>>(3 * spectrum_size);
  has_scene_.assign(static_cast<std::size_t>(slots), false);
  // Row buffers: every row starts a multiple of 64 bytes after the first, so that all keep the
  // alignment of fftwf_malloc's arrays that the row plans were made for.
  row_stride_ = (cols_ + 15) / 16 * 16;
  tile_stride_ = (cols_ / 2 + 1 + 7) / 8 * 8;
  for (int t = 0; t < threads_; ++t)
    row_scratch_.push_back({FftwFloatBuffer<float>(3 * static_cast<std::size_t>(row_stride_)),
                            FftwFloatBuffer<std::complex<float>>(3 * static_cast<std::size_t>(kRowTile) * tile_stride_), 0});
  // Measured plans kept in the wisdom file (glare/cpu/fftw_float_plan.h): FFTW_ESTIMATE's plans of the
  // column passes took 1.6 to 2.2 times FFTW_MEASURE's here (when the columns were strided).
  constexpr FftwPlanning kept = FftwPlanning::kept;
  RowScratch& first_scratch = row_scratch_.front();
  row_forward_ = FftwFloatPlan::real_row_forward(cols_, first_scratch.rows.data(), first_scratch.tile.data(), kept);
  row_inverse_ = FftwFloatPlan::real_row_inverse(cols_, first_scratch.tile.data(), first_scratch.rows.data(), kept);
  // The planning may have written over the row buffer, whose zeros past the rows are relied on.
  std::fill(first_scratch.rows.data(), first_scratch.rows.data() + first_scratch.rows.size(), 0.0f);
  // The column passes: one plan each over all columns.
  image_column_pass_ = FftwFloatPlan::transposed_columns(rows_, cols_, 3, -1, incoming_spectrum_.data(), threads_, kept);
  kernel_column_pass_ = FftwFloatPlan::transposed_columns(rows_, cols_, 3, -1, kernel_spectrum_.data(), threads_, kept);
  inverse_column_pass_ = FftwFloatPlan::transposed_columns(rows_, cols_, 3, +1, product, threads_, kept);
}

template <typename Fill>
bool CpuFloatConvolution::forward_rows(int row_count, int width, std::complex<float>* spectrum, const Fill& fill) {
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * spectrum_cols;
  const int tiles = (row_count + kRowTile - 1) / kRowTile;
  std::atomic<bool> accepted = true;
  parallel_indexed_chunks(tiles, threads_, [&](int chunk, int first_tile, int last_tile) {
    RowScratch& scratch = row_scratch_[static_cast<std::size_t>(chunk)];
    float* const rgb[3] = {scratch_row(scratch, 0), scratch_row(scratch, 1), scratch_row(scratch, 2)};
    // The values past `width` are the transform's zero padding: clear what a wider fill left there.
    if (scratch.written_width > width)
      for (float* channel : rgb) std::fill(channel + width, channel + scratch.written_width, 0.0f);
    scratch.written_width = width;
    bool chunk_accepted = true;
    for (int tile = first_tile; tile < last_tile; ++tile) {
      const int row0 = tile * kRowTile, rows = std::min(kRowTile, row_count - row0);
      for (int r = 0; r < rows; ++r) {
        chunk_accepted = fill(row0 + r, rgb[0], rgb[1], rgb[2]) && chunk_accepted;
        for (int c = 0; c < 3; ++c)
          row_forward_.execute(rgb[c], tile_row(scratch, c, r));
      }
      // Transposed: the tile's rows are kRowTile consecutive values of each column.
      for (int c = 0; c < 3; ++c)
        transpose_complex(tile_row(scratch, c, 0), static_cast<std::size_t>(tile_stride_), rows, spectrum_cols,
                          spectrum + c * spectrum_size + row0, static_cast<std::size_t>(rows_));
    }
    if (!chunk_accepted) accepted = false;
  });
  return accepted;
}

template <typename Emit>
void CpuFloatConvolution::inverse_rows(std::complex<float>* product, int first_row, int row_count, const Emit& emit) {
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  const std::size_t spectrum_size = static_cast<std::size_t>(rows_) * spectrum_cols;
  const int tiles = (row_count + kRowTile - 1) / kRowTile;
  parallel_indexed_chunks(tiles, threads_, [&](int chunk, int first_tile, int last_tile) {
    RowScratch& scratch = row_scratch_[static_cast<std::size_t>(chunk)];
    float* const rgb[3] = {scratch_row(scratch, 0), scratch_row(scratch, 1), scratch_row(scratch, 2)};
    scratch.written_width = cols_;  // the rows are written whole: forward_rows clears past its width
    for (int tile = first_tile; tile < last_tile; ++tile) {
      const int row0 = first_row + tile * kRowTile, rows = std::min(kRowTile, first_row + row_count - row0);
      // kRowTile consecutive values of each column are the tile's rows.
      for (int c = 0; c < 3; ++c)
        transpose_complex(product + c * spectrum_size + row0, static_cast<std::size_t>(rows_),
                          static_cast<int>(spectrum_cols), static_cast<std::size_t>(rows), tile_row(scratch, c, 0),
                          static_cast<std::size_t>(tile_stride_));
      for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < 3; ++c)
          row_inverse_.execute(tile_row(scratch, c, r), rgb[c]);
        emit(row0 + r, rgb[0], rgb[1], rgb[2]);
      }
    }
  });
}

void CpuFloatConvolution::clear_rows(std::complex<float>* spectrum, int first_row) const {
  // Transposed spectra: rows [first_row, rows) are the tail of each of the 3 (cols/2 + 1) columns.
  const int columns = 3 * (cols_ / 2 + 1);
  const std::size_t rows = static_cast<std::size_t>(rows_);
  parallel_chunks(columns, threads_, [&](int first, int last) {
    for (int k = first; k < last; ++k)
      std::fill(spectrum + k * rows + first_row, spectrum + (k + 1) * rows, std::complex<float>{});
  });
}

void CpuFloatConvolution::transform_scene(const ImageRGBA& image, int x0, int y0, int slot) {
  if (slot < 0 || slot >= slots_) throw std::invalid_argument("glare/cpu/float_convolution: no scene slot " + std::to_string(slot));
  // `same` output keeps the scene's alpha for convolve() (not the whole scene: a copy of it was a
  // frame-sized pass of its own), read into incoming_alpha_ and swapped in once the scene is
  // accepted, as is its spectrum, so that a refused scene leaves the last one's.
  const bool keep_alpha = output_ == ConvolutionOutput::same;
  if (keep_alpha) incoming_alpha_.resize(static_cast<std::size_t>(width_) * height_);
  const bool clean = forward_rows(height_, width_, incoming_spectrum_.data(), [&](int y, float* red, float* green, float* blue) {
    // A negative or non-finite R, G or B (NaN included) is refused, as convolve_image_cpu refuses it.
    float* alpha = keep_alpha ? &incoming_alpha_[static_cast<std::size_t>(y) * width_] : nullptr;
    return split_rgba_row(image.pixel(x0, y0 + y), width_, red, green, blue, alpha);
  });
  if (!clean) {
    ImageRGBA region(width_, height_);
    for (int y = 0; y < height_; ++y) std::copy_n(image.pixel(x0, y0 + y), 4 * width_, region.pixel(0, y));
    throw std::invalid_argument("glare/cpu/float_convolution: the image cannot be convolved: it has " +
                                inspect_pixels(region).describe());
  }
  clear_rows(incoming_spectrum_.data(), height_);
  image_column_pass_.execute(incoming_spectrum_.data(), incoming_spectrum_.data());
  std::swap(incoming_spectrum_, scene_spectra_[static_cast<std::size_t>(slot)]);
  if (keep_alpha) scene_alpha_.swap(incoming_alpha_);
  has_scene_[static_cast<std::size_t>(slot)] = true;
}

void CpuFloatConvolution::set_scene(const ImageRGBA& image, int slot) {
  if (image.width_px != width_ || image.height_px != height_)
    throw std::invalid_argument("glare/cpu/float_convolution: the image is " + std::to_string(image.width_px) + " x " +
                                std::to_string(image.height_px) + ", planned for " + std::to_string(width_) + " x " +
                                std::to_string(height_));
  // transform_scene refuses non-finite and negative pixels as it copies them (no scan before it).
  transform_scene(image, 0, 0, slot);
  if (output_ == ConvolutionOutput::same) scene_depth_ = image.depth;
}

void CpuFloatConvolution::set_scene(const ImageRGBA& frame, int x0, int y0, int slot) {
  if (x0 < 0 || y0 < 0 || x0 + width_ > frame.width_px || y0 + height_ > frame.height_px)
    throw std::invalid_argument("glare/cpu/float_convolution: the region does not lie inside the frame");
  transform_scene(frame, x0, y0, slot);
}

void CpuFloatConvolution::set_kernel(const Psf& psf) {
  if (psf.size_px != kernel_px_ || (psf.channels != 1 && psf.channels != 3))
    throw std::invalid_argument("glare/cpu/float_convolution: the PSF is not the planned size, or not 1 or 3 channels");
  const int m = kernel_px_;
  forward_rows(m, m, kernel_spectrum_.data(), [&](int y, float* red, float* green, float* blue) {
    float* const targets[3] = {red, green, blue};
    for (int c = 0; c < 3; ++c) {
      const double* source = &psf.values[(static_cast<std::size_t>(psf.channels == 3 ? c : 0) * m + y) * m];
      for (int x = 0; x < m; ++x) targets[c][x] = static_cast<float>(source[x]);
    }
    return true;
  });
  clear_rows(kernel_spectrum_.data(), kernel_px_);
  kernel_column_pass_.execute();
  has_kernel_ = true;
}

std::complex<float>* CpuFloatConvolution::multiply_and_invert_columns(int slot) {
  // The product of the spectra, with the 1 / (rows cols) of the unnormalised inverse folded in.
  const float inverse_size = static_cast<float>(1.0 / (static_cast<double>(rows_) * cols_));
  const int spectrum_rows = 3 * rows_;
  const std::size_t spectrum_cols = static_cast<std::size_t>(cols_ / 2 + 1);
  // Written out: std::complex's operator* checks for NaN (C99 Annex G), which costs here and cannot
  // trigger (scenes with non-finite pixels are refused, the PSF is finite).
  const float* kernel = reinterpret_cast<const float*>(kernel_spectrum_.data());
  const float* image = reinterpret_cast<const float*>(spectrum(slot));
  std::complex<float>* product_spectrum = output_ == ConvolutionOutput::full ? product_.data() : kernel_spectrum_.data();
  float* product = reinterpret_cast<float*>(product_spectrum);
  parallel_chunks(spectrum_rows, threads_, [&](int first, int last) {
    for (std::size_t k = 2 * first * spectrum_cols; k < 2 * last * spectrum_cols; k += 2) {
      const float a = kernel[k], b = kernel[k + 1], c = image[k] * inverse_size, d = image[k + 1] * inverse_size;
      product[k] = a * c - b * d;
      product[k + 1] = a * d + b * c;
    }
  });
  inverse_column_pass_.execute();
  return product_spectrum;
}

void CpuFloatConvolution::convolve(const Psf& psf, ImageRGBA& out) {
  if (output_ != ConvolutionOutput::same) throw std::logic_error("glare/cpu/float_convolution: convolve needs `same` output");
  if (!has_scene_[0]) throw std::logic_error("glare/cpu/float_convolution: convolve before set_scene");
  set_kernel(psf);
  std::complex<float>* product = multiply_and_invert_columns(0);
  const int half = kernel_px_ / 2;
  // full(y, x) = sum img(y', x') psf(y - y', x - x'); the PSF's centre is (M/2, M/2): output row y is
  // full row y + M/2, output column x full column x + M/2.
  if (out.width_px != width_ || out.height_px != height_ || out.rgba.size() != 4 * scene_alpha_.size())
    out = ImageRGBA(width_, height_);
  out.depth = scene_depth_;
  inverse_rows(product, half, height_, [&](int row, const float* red, const float* green, const float* blue) {
    const int y = row - half;
    join_rgba_row(red + half, green + half, blue + half, &scene_alpha_[static_cast<std::size_t>(y) * width_], width_,
                  out.pixel(0, y));
  });
}

void CpuFloatConvolution::write_full(int slot, ImageRGBA& frame, int x0, int y0, const RowFinish* finish,
                                     FullWrite write) {
  if (output_ != ConvolutionOutput::full) throw std::logic_error("glare/cpu/float_convolution: write_full needs `full` output");
  if (slot < 0 || slot >= slots_ || !has_scene_[static_cast<std::size_t>(slot)] || !has_kernel_)
    throw std::logic_error("glare/cpu/float_convolution: write_full before set_scene and set_kernel");
  const int m = kernel_px_;
  // Full index (fy, fx) is frame pixel (y0 - M/2 + fy, x0 - M/2 + fx), for fy < height + M - 1.
  const int fy0 = std::max(0, m / 2 - y0), fy1 = std::min(height_ + m - 1, frame.height_px - y0 + m / 2);
  const int fx0 = std::max(0, m / 2 - x0), fx1 = std::min(width_ + m - 1, frame.width_px - x0 + m / 2);
  if (fy1 <= fy0 || fx1 <= fx0) return;
  std::complex<float>* product = multiply_and_invert_columns(slot);
  inverse_rows(product, fy0, fy1 - fy0, [&](int fy, const float* red, const float* green, const float* blue) {
    float* const row = frame.pixel(x0 - m / 2 + fx0, y0 - m / 2 + fy);
    float* target = row;
    if (write == FullWrite::add)
      for (int fx = fx0; fx < fx1; ++fx, target += 4) {
        target[0] += red[fx];
        target[1] += green[fx];
        target[2] += blue[fx];
      }
    else
      for (int fx = fx0; fx < fx1; ++fx, target += 4) {
        target[0] = red[fx];
        target[1] = green[fx];
        target[2] = blue[fx];
      }
    if (finish != nullptr) (*finish)(y0 - m / 2 + fy, x0 - m / 2 + fx0, x0 - m / 2 + fx1, row);
  });
}

}  // namespace glarelab
