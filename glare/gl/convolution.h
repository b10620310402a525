#pragma once
// Convolution of an HDR image (core/image.h, R, G, B) with a PSF (glare/wave/psf.h) on the GPU by FFT
// (Ritschel et al. 2009, section 5): both zero-padded to a length of 2s, 3s and 5s at least image +
// PSF - 1 in each direction (padded_fft_length), so nothing wraps around an edge and any image size
// works; pointwise complex product; inverse FFT; the image-sized window read back. Alpha is passed
// through. Real layers travel two to a complex layer: R + iG and B, and a three-channel PSF's
// K_R + iK_G and K_B, so an image, a PSF or a product takes two transforms instead of three
// (complex_multiply.comp separates the packed spectra by their Hermitian symmetry). Both spectra
// are kept for the next call: an image that comes again (a static scene under dynamic glare) is
// neither checked, split, uploaded nor transformed again, nor is a PSF that comes again. The padding and
// the window are made on the GPU (convolution_pad_image.comp, convolution_pad_kernel.comp,
// convolution_crop.comp): only the image and the PSF go to the GPU and only the result comes back,
// not the padded complex layers (4 x 8 bytes per padded pixel each way).
//
// Dynamic range: the float32 FFT spreads rounding noise of about 1e-7 of the brightest pixel's
// energy over the whole frame, which swamps a 1e-2 cd/m2 surround next to a 1e8 cd/m2 source. So
// pixels brighter than split_dynamic_range times the median pixel are taken out of the FFT and added
// by direct summation (bright_splat.comp); convolution is linear, so the sum is the same function.
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "glare/gl/fft.h"
#include "glare/wave/psf.h"
#include "core/image.h"

namespace glarelab::gl {

struct GlConvolutionOptions {
  bool split_bright = true;
  double split_dynamic_range = 1e4;          // bright: max(R, G, B) > this x median over pixels of max(R, G, B)
  std::size_t max_direct_bright_pixels = 4096;  // beyond this the split is not made (cost: pixels x bright pixels)
  // A token the caller gives this image and no other (0: none). The same token as the image whose
  // spectrum is kept is that image, known without comparing its pixels (33 MB at 1920 x 1080); with
  // no token the pixels are compared.
  std::uint64_t image_token = 0;
};

struct GlConvolutionReport {
  int padded_width_px = 0;
  int padded_height_px = 0;
  bool split = false;
  std::size_t bright_pixels = 0;
  double bright_threshold = 0.0;  // in the image's units (cd/m2 for a calibrated image)
  bool psf_spectrum_reused = false;  // the same PSF as the previous call: its FFT was not redone
  // The same image (and split) as the previous call: its checks, split, upload and FFT were not redone.
  bool image_spectrum_reused = false;
  // The GPU's time from the image's upload to the result's read-back (GL timestamp queries): the
  // convolution without the host's checks and split, which the call's wall time adds.
  double gpu_s = 0.0;
  // gpu_s by stage, in the order they run (GL timestamp queries between them): "image up + pad",
  // "PSF spectrum" (up, pad, FFT; 0 when reused), "image FFT", "product", "inverse FFT",
  // "bright sum" (0 without a split), "crop", "read back".
  std::vector<std::pair<std::string, double>> gpu_stages_s;
  std::string describe() const;
  std::string describe_gpu_stages() const;  // e.g. "image up + pad 0.31 ms, PSF spectrum 0.52 ms, ..."
};

class GlConvolution {
 public:
  GlConvolution();
  ~GlConvolution();
  GlConvolution(const GlConvolution&) = delete;
  GlConvolution& operator=(const GlConvolution&) = delete;

  // Throws std::invalid_argument("GL convolution: ...") for an empty image, NaN/Inf/negative pixels
  // (with their counts), a malformed PSF, or a padded size above 4096.
  ImageRGBA convolve(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options = {},
                     GlConvolutionReport* report = nullptr);
  // The same convolution left on the GPU: the name of the buffer holding the result (RGBA32F,
  // width x height, row 0 first as in ImageRGBA), nothing read back. The buffer is this object's,
  // valid until its next call; the report's "read back" stage is then 0.
  GLuint convolve_on_gpu(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options = {},
                         GlConvolutionReport* report = nullptr);
  // Drops the kept PSF spectrum, so the next call transforms its PSF again (as for a new PSF each
  // frame in dynamic glare; the benchmark times that case).
  void forget_psf() { kernel_ready_ = false; }
  // Drops the kept image spectrum, so the next call checks, splits and transforms its image again
  // (a new scene; the benchmark times both).
  void forget_image();

 private:
  struct Ffts;
  struct ImageSpectrum;
  struct Grid;
  // convolve()'s steps, in its order: the image checked and split into bright and dim parts (on
  // the CPU), the dim part padded onto the grid, the PSF padded and transformed, the spectra
  // multiplied, the bright pixels added directly, the result cropped; then the stages' GPU times.
  // convolve() and convolve_on_gpu(): the result read back into `output` unless it is null.
  void run(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options, GlConvolutionReport* report,
           ImageRGBA* output);
  static std::unique_ptr<ImageSpectrum> split_image(const ImageRGBA& image, const GlConvolutionOptions& options);
  void pad_image(const ImageRGBA& image, const ImageSpectrum& scene, const Grid& grid);
  void transform_psf(const Psf& psf, const Grid& grid);
  void multiply_spectra(const Grid& grid);
  void add_bright_pixels(const ImageSpectrum& scene, const Grid& grid);
  void crop(const Grid& grid, std::size_t image_bytes);
  void read_gpu_stages(GlConvolutionReport& report) const;
  std::unique_ptr<Ffts> ffts_;  // reused while the padded size and PSF channel count stay the same
  std::unique_ptr<ImageSpectrum> image_spectrum_;  // what ffts_->image holds; null when nothing
  Program multiply_program_, splat_program_, pad_image_program_, pad_kernel_program_, crop_program_;
  Buffer image_, result_;  // the image in and the convolved image out, RGBA, width x height
  std::vector<Query> timestamps_;  // one before the first stage and one after each
  Buffer bright_, bright_values_, kernel_;
  std::size_t image_bytes_ = 0, result_bytes_ = 0, bright_bytes_ = 0, bright_values_bytes_ = 0, kernel_bytes_ = 0;
  bool kernel_ready_ = false;  // ffts_->kernel holds the spectrum of the PSF below
  int cached_psf_size_ = 0;
  std::vector<double> cached_psf_values_;
};

// The padded grid's side for `length` pixels: the smallest length the GL FFT takes (2^a 3^b 5^c, at
// least kFftMinLength) that is >= length; 0 when above kFftMaxLength. A 1920 x 1080 frame with a
// 256-pixel PSF pads to 2187 x 1350, where powers of two would take 4096 x 2048.
int padded_fft_length(int length);

}  // namespace glarelab::gl
