#include "glare/gl/gl_convolution.h"

#include <algorithm>
#include <complex>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

constexpr GLuint kMultiplyGroup = 256;
// At most this many groups per dispatch (262 144 invocations): OpenGL guarantees only 65535 per
// dimension and three 4096 x 4096 layers need 196 608; complex_multiply.comp strides over the rest
// (from a 512 x 256 padded frame on, so the convolution tests run the loop).
constexpr GLuint kMaxMultiplyGroups = 1024;
constexpr GLuint kTile = 8;

void validate(const ImageRGBA& image, const Psf& psf) {
  if (image.empty()) throw std::invalid_argument("GL convolution: the image is empty");
  const NonFiniteReport pixels = inspect_pixels(image);
  if (!pixels.clean()) throw std::invalid_argument("GL convolution: the image has " + pixels.describe());
  if (psf.size_px < 1 || (psf.channels != 1 && psf.channels != 3) ||
      psf.values.size() != static_cast<std::size_t>(psf.channels) * psf.size_px * psf.size_px)
    throw std::invalid_argument("GL convolution: malformed PSF (size " + std::to_string(psf.size_px) + ", " +
                                std::to_string(psf.channels) + " channels, " + std::to_string(psf.values.size()) +
                                " values)");
}

float max_channel(const float* p) { return std::max({p[0], p[1], p[2]}); }

}  // namespace

int padded_fft_length(int length) {
  int padded = kFftMinLength;
  while (padded < length && padded <= kFftMaxLength) padded *= 2;
  return padded <= kFftMaxLength ? padded : 0;
}

std::string GlConvolutionReport::describe() const {
  std::ostringstream text;
  text << "GL convolution on a " << padded_width_px << " x " << padded_height_px << " padded grid"
       << (psf_spectrum_reused ? " (PSF spectrum reused)" : "");
  if (split)
    text << "; " << bright_pixels << " bright pixel(s) above " << bright_threshold << " summed directly";
  else if (bright_pixels > 0)
    text << "; not split: " << bright_pixels << " bright pixel(s) above " << bright_threshold
         << " exceed the direct-summation limit";
  return text.str();
}

struct GlConvolution::Ffts {
  GlFft image;
  GlFft kernel;
};

GlConvolution::GlConvolution()
    : multiply_program_(build_program({"glare/shaders/complex_multiply.comp"})),
      splat_program_(build_program({"glare/shaders/bright_splat.comp"})),
      bright_(create_buffer()),
      bright_values_(create_buffer()),
      kernel_(create_buffer()) {}

GlConvolution::~GlConvolution() = default;

ImageRGBA GlConvolution::convolve(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options,
                                  GlConvolutionReport* report) {
  validate(image, psf);
  const int width = image.width_px, height = image.height_px, k = psf.size_px;
  const int padded_width = padded_fft_length(width + k - 1);
  const int padded_height = padded_fft_length(height + k - 1);
  if (padded_width == 0 || padded_height == 0)
    throw std::invalid_argument("GL convolution: image " + std::to_string(width) + " x " + std::to_string(height) +
                                " with a " + std::to_string(k) + " px PSF needs a padded grid above " +
                                std::to_string(kFftMaxLength));
  if (!ffts_ || ffts_->image.width() != padded_width || ffts_->image.height() != padded_height ||
      ffts_->kernel.layers() != psf.channels) {
    ffts_ = std::make_unique<Ffts>(Ffts{GlFft(padded_width, padded_height, 3), GlFft(padded_width, padded_height, psf.channels)});
    kernel_ready_ = false;
  }
  const std::size_t layer = static_cast<std::size_t>(padded_width) * padded_height;

  // Split into bright (summed directly) and dim (by FFT) parts.
  GlConvolutionReport local_report;
  local_report.padded_width_px = padded_width;
  local_report.padded_height_px = padded_height;
  std::vector<float> bright_positions, bright_values;
  std::vector<char> is_bright(static_cast<std::size_t>(width) * height, 0);
  if (options.split_bright) {
    std::vector<float> maxima;
    maxima.reserve(is_bright.size());
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) maxima.push_back(max_channel(image.pixel(x, y)));
    std::nth_element(maxima.begin(), maxima.begin() + static_cast<std::ptrdiff_t>(maxima.size() / 2), maxima.end());
    const double median = maxima[maxima.size() / 2];
    local_report.bright_threshold = options.split_dynamic_range * median;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* p = image.pixel(x, y);
        if (max_channel(p) > local_report.bright_threshold) {
          ++local_report.bright_pixels;
          is_bright[static_cast<std::size_t>(y) * width + x] = 1;
          bright_positions.insert(bright_positions.end(), {static_cast<float>(x), static_cast<float>(y), 0.0f, 0.0f});
          bright_values.insert(bright_values.end(), {p[0], p[1], p[2], 0.0f});
        }
      }
    local_report.split = local_report.bright_pixels > 0 && local_report.bright_pixels <= options.max_direct_bright_pixels;
    if (!local_report.split) std::fill(is_bright.begin(), is_bright.end(), 0);
  }

  std::vector<std::complex<float>> padded(3 * layer);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (is_bright[static_cast<std::size_t>(y) * width + x]) continue;
      const float* p = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) padded[c * layer + static_cast<std::size_t>(y) * padded_width + x] = p[c];
    }
  ffts_->image.upload(padded);

  // PSF centre (k/2, k/2) at index (0, 0), wrapping: circular convolution equals linear
  // convolution on the image window because the padding is at least k - 1. The PSF's spectrum is
  // kept while the same PSF comes again on the same padded grid (static glare, successive frames).
  const bool kernel_cached = kernel_ready_ && cached_psf_size_ == k && cached_psf_values_ == psf.values;
  if (!kernel_cached) {
    std::vector<std::complex<float>> kernel(static_cast<std::size_t>(psf.channels) * layer);
    for (int c = 0; c < psf.channels; ++c)
      for (int v = 0; v < k; ++v)
        for (int u = 0; u < k; ++u) {
          const int x = (u - k / 2 + padded_width) % padded_width, y = (v - k / 2 + padded_height) % padded_height;
          kernel[c * layer + static_cast<std::size_t>(y) * padded_width + x] = static_cast<float>(psf.at(c, u, v));
        }
    ffts_->kernel.upload(kernel);
    ffts_->kernel.transform(FftDirection::forward);
    cached_psf_size_ = k;
    cached_psf_values_ = psf.values;
    kernel_ready_ = true;
  }
  local_report.psf_spectrum_reused = kernel_cached;

  ffts_->image.transform(FftDirection::forward);
  const GLuint multiply = multiply_program_.get();
  glUseProgram(multiply);
  glUniform1ui(glGetUniformLocation(multiply, "uLayerSize"), static_cast<GLuint>(layer));
  glUniform1ui(glGetUniformLocation(multiply, "uImageLayers"), 3u);
  glUniform1ui(glGetUniformLocation(multiply, "uKernelLayers"), static_cast<GLuint>(psf.channels));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ffts_->kernel.data());
  glDispatchCompute(std::min((static_cast<GLuint>(3 * layer) + kMultiplyGroup - 1) / kMultiplyGroup, kMaxMultiplyGroups), 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  ffts_->image.transform(FftDirection::inverse);

  if (local_report.split) {
    std::vector<float> psf_values(psf.values.begin(), psf.values.end());
    glNamedBufferData(bright_.get(), static_cast<GLsizeiptr>(bright_positions.size() * sizeof(float)),
                      bright_positions.data(), GL_DYNAMIC_DRAW);
    glNamedBufferData(bright_values_.get(), static_cast<GLsizeiptr>(bright_values.size() * sizeof(float)),
                      bright_values.data(), GL_DYNAMIC_DRAW);
    glNamedBufferData(kernel_.get(), static_cast<GLsizeiptr>(psf_values.size() * sizeof(float)), psf_values.data(),
                      GL_DYNAMIC_DRAW);
    const GLuint splat = splat_program_.get();
    glUseProgram(splat);
    glUniform1i(glGetUniformLocation(splat, "uWidth"), width);
    glUniform1i(glGetUniformLocation(splat, "uHeight"), height);
    glUniform1i(glGetUniformLocation(splat, "uPaddedWidth"), padded_width);
    glUniform1i(glGetUniformLocation(splat, "uLayerSize"), static_cast<GLint>(layer));
    glUniform1i(glGetUniformLocation(splat, "uKernelSize"), k);
    glUniform1i(glGetUniformLocation(splat, "uKernelLayers"), psf.channels);
    glUniform1i(glGetUniformLocation(splat, "uBrightCount"), static_cast<GLint>(local_report.bright_pixels));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, bright_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, bright_values_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, kernel_.get());
    glDispatchCompute((static_cast<GLuint>(width) + kTile - 1) / kTile, (static_cast<GLuint>(height) + kTile - 1) / kTile, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  glUseProgram(0);
  check_gl_error("GL convolution");

  const std::vector<std::complex<float>> result = ffts_->image.download();
  ImageRGBA output(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = output.pixel(x, y);
      for (int c = 0; c < 3; ++c) p[c] = result[c * layer + static_cast<std::size_t>(y) * padded_width + x].real();
      p[3] = image.pixel(x, y)[3];
    }
  if (report != nullptr) *report = local_report;
  return output;
}

}  // namespace glarelab::gl
