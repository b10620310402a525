#include "glare/gl/gl_convolution.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
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
constexpr GLuint kPadTile = 16;  // convolution_pad_*.comp, convolution_crop.comp

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

// Workgroups of `tile` along one axis to cover `count` invocations.
GLuint groups_of(int count, GLuint tile) { return (static_cast<GLuint>(count) + tile - 1) / tile; }

// The image and padded-grid sizes of the pad and crop passes (convolution_pad_image.comp,
// convolution_crop.comp).
void set_grid_uniforms(GLuint program, int width, int height, int padded_width, int padded_height) {
  glUniform1i(glGetUniformLocation(program, "uWidth"), width);
  glUniform1i(glGetUniformLocation(program, "uHeight"), height);
  glUniform1i(glGetUniformLocation(program, "uPaddedWidth"), padded_width);
  glUniform1i(glGetUniformLocation(program, "uPaddedHeight"), padded_height);
}

// The pixels summed directly (bright_splat.comp) and their bounding box.
struct BrightPixels {
  std::vector<float> positions;  // x, y, 0, 0 per pixel
  std::vector<float> values;     // R, G, B, 0 per pixel
  int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max(), x1 = -1, y1 = -1;
  void add(int x, int y, const float* p) {
    positions.insert(positions.end(), {static_cast<float>(x), static_cast<float>(y), 0.0f, 0.0f});
    values.insert(values.end(), {p[0], p[1], p[2], 0.0f});
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  }
  std::size_t count() const { return positions.size() / 4; }
};

// The largest float at or below `value`: for a float v, v > value exactly when v > this.
float float_at_or_below(double value) {
  float rounded = static_cast<float>(value);
  if (static_cast<double>(rounded) > value) rounded = std::nextafter(rounded, -std::numeric_limits<float>::infinity());
  return rounded;
}

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
      pad_image_program_(build_program({"glare/shaders/convolution_pad_image.comp"})),
      pad_kernel_program_(build_program({"glare/shaders/convolution_pad_kernel.comp"})),
      crop_program_(build_program({"glare/shaders/convolution_crop.comp"})),
      image_(create_buffer()),
      result_(create_buffer()),
      gpu_start_(create_query(GL_TIMESTAMP)),
      gpu_end_(create_query(GL_TIMESTAMP)),
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

  // Split into bright (summed directly) and dim (by FFT) parts. The threshold is found here (the
  // median); the pad pass on the GPU leaves the bright pixels out by the same comparison.
  GlConvolutionReport local_report;
  local_report.padded_width_px = padded_width;
  local_report.padded_height_px = padded_height;
  BrightPixels bright;
  if (options.split_bright) {
    std::vector<float> maxima;
    maxima.reserve(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) maxima.push_back(max_channel(image.pixel(x, y)));
    std::nth_element(maxima.begin(), maxima.begin() + static_cast<std::ptrdiff_t>(maxima.size() / 2), maxima.end());
    const double median = maxima[maxima.size() / 2];
    local_report.bright_threshold = options.split_dynamic_range * median;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* p = image.pixel(x, y);
        if (max_channel(p) > local_report.bright_threshold) bright.add(x, y, p);
      }
    local_report.bright_pixels = bright.count();
    local_report.split = local_report.bright_pixels > 0 && local_report.bright_pixels <= options.max_direct_bright_pixels;
  }
  const float pad_threshold =
      local_report.split ? float_at_or_below(local_report.bright_threshold) : std::numeric_limits<float>::max();

  glQueryCounter(gpu_start_.get(), GL_TIMESTAMP);
  glNamedBufferData(image_.get(), static_cast<GLsizeiptr>(image.rgba.size() * sizeof(float)), image.rgba.data(),
                    GL_DYNAMIC_DRAW);
  const GLuint groups_x = groups_of(padded_width, kPadTile), groups_y = groups_of(padded_height, kPadTile);
  const GLuint pad_image = pad_image_program_.get();
  glUseProgram(pad_image);
  set_grid_uniforms(pad_image, width, height, padded_width, padded_height);
  glUniform1f(glGetUniformLocation(pad_image, "uBrightThreshold"), pad_threshold);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, image_.get());
  glDispatchCompute(groups_x, groups_y, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  // The PSF's spectrum is kept while the same PSF comes again on the same padded grid (static
  // glare, successive frames).
  const bool kernel_cached = kernel_ready_ && cached_psf_size_ == k && cached_psf_values_ == psf.values;
  if (!kernel_cached || local_report.split) {
    const std::vector<float> psf_values(psf.values.begin(), psf.values.end());
    glNamedBufferData(kernel_.get(), static_cast<GLsizeiptr>(psf_values.size() * sizeof(float)), psf_values.data(),
                      GL_DYNAMIC_DRAW);
  }
  if (!kernel_cached) {
    const GLuint pad_kernel = pad_kernel_program_.get();
    glUseProgram(pad_kernel);
    glUniform1i(glGetUniformLocation(pad_kernel, "uPaddedWidth"), padded_width);
    glUniform1i(glGetUniformLocation(pad_kernel, "uPaddedHeight"), padded_height);
    glUniform1i(glGetUniformLocation(pad_kernel, "uKernelSize"), k);
    glUniform1i(glGetUniformLocation(pad_kernel, "uKernelLayers"), psf.channels);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->kernel.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, kernel_.get());
    glDispatchCompute(groups_x, groups_y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
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
    glNamedBufferData(bright_.get(), static_cast<GLsizeiptr>(bright.positions.size() * sizeof(float)),
                      bright.positions.data(), GL_DYNAMIC_DRAW);
    glNamedBufferData(bright_values_.get(), static_cast<GLsizeiptr>(bright.values.size() * sizeof(float)),
                      bright.values.data(), GL_DYNAMIC_DRAW);
    const GLuint splat = splat_program_.get();
    glUseProgram(splat);
    glUniform1i(glGetUniformLocation(splat, "uWidth"), width);
    glUniform1i(glGetUniformLocation(splat, "uHeight"), height);
    glUniform1i(glGetUniformLocation(splat, "uPaddedWidth"), padded_width);
    glUniform1i(glGetUniformLocation(splat, "uLayerSize"), static_cast<GLint>(layer));
    glUniform1i(glGetUniformLocation(splat, "uKernelSize"), k);
    glUniform1i(glGetUniformLocation(splat, "uKernelLayers"), psf.channels);
    glUniform1i(glGetUniformLocation(splat, "uBrightCount"), static_cast<GLint>(local_report.bright_pixels));
    // Only pixels within the PSF's reach of a bright pixel receive anything: the bright pixels'
    // bounding box grown by the reach: bright_splat.comp's offset pixel - bright + K/2 lies in
    // [0, K), so K/2 on the low side and K - 1 - K/2 on the high side.
    const int x0 = std::max(0, bright.x0 - k / 2), y0 = std::max(0, bright.y0 - k / 2);
    const int x1 = std::min(width - 1, bright.x1 + (k - 1 - k / 2));
    const int y1 = std::min(height - 1, bright.y1 + (k - 1 - k / 2));
    glUniform2i(glGetUniformLocation(splat, "uOrigin"), x0, y0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, bright_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, bright_values_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, kernel_.get());
    glDispatchCompute(groups_of(x1 - x0 + 1, kTile), groups_of(y1 - y0 + 1, kTile), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }

  glNamedBufferData(result_.get(), static_cast<GLsizeiptr>(image.rgba.size() * sizeof(float)), nullptr, GL_DYNAMIC_READ);
  const GLuint crop = crop_program_.get();
  glUseProgram(crop);
  set_grid_uniforms(crop, width, height, padded_width, padded_height);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, image_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, result_.get());
  glDispatchCompute(groups_of(width, kPadTile), groups_of(height, kPadTile), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  ImageRGBA output(width, height);
  glGetNamedBufferSubData(result_.get(), 0, static_cast<GLsizeiptr>(output.rgba.size() * sizeof(float)), output.rgba.data());
  glQueryCounter(gpu_end_.get(), GL_TIMESTAMP);
  check_gl_error("GL convolution");
  GLuint64 start_ns = 0, end_ns = 0;
  glGetQueryObjectui64v(gpu_start_.get(), GL_QUERY_RESULT, &start_ns);
  glGetQueryObjectui64v(gpu_end_.get(), GL_QUERY_RESULT, &end_ns);
  local_report.gpu_s = end_ns > start_ns ? 1e-9 * static_cast<double>(end_ns - start_ns) : 0.0;
  if (report != nullptr) *report = local_report;
  return output;
}

}  // namespace glarelab::gl
