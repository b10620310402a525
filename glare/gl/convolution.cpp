#include "glare/gl/convolution.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "core/fft_size.h"
#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

constexpr GLuint kMultiplyGroup = 256;
// At most this many groups per dispatch (262 144 invocations): OpenGL guarantees only 65535 per
// dimension and a 4096 x 4096 layer needs 65 536; complex_multiply.comp strides over the rest
// (from a 512 x 512 padded layer on, so the convolution tests run the loop).
constexpr GLuint kMaxMultiplyGroups = 1024;
constexpr GLuint kTile = 8;
constexpr GLuint kPadTile = 16;  // convolution_pad_*.comp, convolution_crop.comp
constexpr const char* kStageNames[] = {"image up + pad", "PSF spectrum", "image FFT", "product",
                                       "inverse FFT",    "bright sum",   "crop",      "read back"};

void validate_psf(const Psf& psf) {
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

// Complex layers a real layers' count takes packed two to one (R + iG, B).
int packed_layers(int real_layers) { return (real_layers + 1) / 2; }

}  // namespace

int padded_fft_length(int length) {
  const int padded = smooth_fft_size(std::max(length, kFftMinLength));
  return padded <= kFftMaxLength ? padded : 0;
}

std::string GlConvolutionReport::describe() const {
  std::ostringstream text;
  text << "GL convolution on a " << padded_width_px << " x " << padded_height_px << " padded grid"
       << (image_spectrum_reused ? " (image spectrum reused)" : "")
       << (psf_spectrum_reused ? " (PSF spectrum reused)" : "");
  if (split)
    text << "; " << bright_pixels << " bright pixel(s) above " << bright_threshold << " summed directly";
  else if (bright_pixels > 0)
    text << "; not split: " << bright_pixels << " bright pixel(s) above " << bright_threshold
         << " exceed the direct-summation limit";
  return text.str();
}

std::string GlConvolutionReport::describe_gpu_stages() const {
  std::ostringstream text;
  text.precision(3);
  for (const auto& [name, seconds] : gpu_stages_s)
    text << (text.tellp() > 0 ? ", " : "") << name << " " << 1e3 * seconds << " ms";
  return text.str();
}

struct GlConvolution::Ffts {
  GlFft image;    // the dim part of the image (R + iG, B), then its spectrum (kept: ImageSpectrum)
  GlFft kernel;   // the PSF (K, or K_R + iK_G and K_B), then its spectrum (kept while the PSF stays)
  GlFft product;  // their product, then the convolved layers (R + iG, B)
};

GlConvolution::GlConvolution()
    : multiply_program_(build_program({"glare/shaders/complex_multiply.comp"})),
      splat_program_(build_program({"glare/shaders/bright_splat.comp"})),
      pad_image_program_(build_program({"glare/shaders/convolution_pad_image.comp"})),
      pad_kernel_program_(build_program({"glare/shaders/convolution_pad_kernel.comp"})),
      crop_program_(build_program({"glare/shaders/convolution_crop.comp"})),
      image_(create_buffer()),
      result_(create_buffer()),
      bright_(create_buffer()),
      bright_values_(create_buffer()),
      kernel_(create_buffer()) {
  for (std::size_t k = 0; k <= std::size(kStageNames); ++k) timestamps_.push_back(create_query(GL_TIMESTAMP));
}

GlConvolution::~GlConvolution() = default;

void GlConvolution::forget_image() { image_spectrum_.reset(); }

namespace {

// Writes `bytes` from `data` into `buffer`, giving it new storage only when its size changes (a
// store of the same size is not re-specified, so the driver need not allocate or orphan it).
void write_buffer(GLuint buffer, std::size_t& held_bytes, std::size_t bytes, const void* data) {
  if (held_bytes != bytes) {
    glNamedBufferData(buffer, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
    held_bytes = bytes;
  } else if (bytes > 0) {
    glNamedBufferSubData(buffer, 0, static_cast<GLsizeiptr>(bytes), data);
  }
}

bool same_split(const GlConvolutionOptions& a, const GlConvolutionOptions& b) {
  return a.split_bright == b.split_bright && a.split_dynamic_range == b.split_dynamic_range &&
         a.max_direct_bright_pixels == b.max_direct_bright_pixels;
}

}  // namespace

struct GlConvolution::ImageSpectrum {
  ImageRGBA image;               // the image whose dim part's spectrum ffts_->image holds
  GlConvolutionOptions options;  // the split it was made with
  BrightPixels bright;           // its bright pixels (summed directly when split)
  double bright_threshold = 0.0;
  bool split = false;
};

// The sizes of one call: the image, the padded grid, the PSF.
struct GlConvolution::Grid {
  int width = 0, height = 0;                // the image, pixels
  int padded_width = 0, padded_height = 0;  // the FFT grid, pixels
  int kernel_px = 0;                        // the PSF's side, K
  int kernel_layers = 0;                    // the PSF's channels (1 or 3)
  std::size_t layer = 0;                    // padded_width x padded_height
};

std::unique_ptr<GlConvolution::ImageSpectrum> GlConvolution::split_image(const ImageRGBA& image,
                                                                         const GlConvolutionOptions& options) {
  const int width = image.width_px, height = image.height_px;
  const NonFiniteReport pixels = inspect_pixels(image);
  if (!pixels.clean()) throw std::invalid_argument("GL convolution: the image has " + pixels.describe());
  auto spectrum = std::make_unique<ImageSpectrum>();
  spectrum->image = image;
  spectrum->options = options;
  // Split into bright (summed directly) and dim (by FFT) parts. The threshold is found here (the
  // median); the pad pass on the GPU leaves the bright pixels out by the same comparison.
  if (options.split_bright) {
    std::vector<float> maxima;
    maxima.reserve(static_cast<std::size_t>(width) * height);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) maxima.push_back(max_channel(image.pixel(x, y)));
    std::nth_element(maxima.begin(), maxima.begin() + static_cast<std::ptrdiff_t>(maxima.size() / 2), maxima.end());
    const double median = maxima[maxima.size() / 2];
    spectrum->bright_threshold = options.split_dynamic_range * median;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* p = image.pixel(x, y);
        if (max_channel(p) > spectrum->bright_threshold) spectrum->bright.add(x, y, p);
      }
    spectrum->split = spectrum->bright.count() > 0 && spectrum->bright.count() <= options.max_direct_bright_pixels;
  }
  return spectrum;
}

void GlConvolution::pad_image(const ImageRGBA& image, const ImageSpectrum& scene, const Grid& grid) {
  const float pad_threshold =
      scene.split ? float_at_or_below(scene.bright_threshold) : std::numeric_limits<float>::max();
  write_buffer(image_.get(), image_bytes_, image.rgba.size() * sizeof(float), image.rgba.data());
  const GLuint program = pad_image_program_.get();
  glUseProgram(program);
  set_grid_uniforms(program, grid.width, grid.height, grid.padded_width, grid.padded_height);
  glUniform1f(glGetUniformLocation(program, "uBrightThreshold"), pad_threshold);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, image_.get());
  glDispatchCompute(groups_of(grid.padded_width, kPadTile), groups_of(grid.padded_height, kPadTile), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  if (scene.split) {
    const BrightPixels& bright = scene.bright;
    write_buffer(bright_.get(), bright_bytes_, bright.positions.size() * sizeof(float), bright.positions.data());
    write_buffer(bright_values_.get(), bright_values_bytes_, bright.values.size() * sizeof(float), bright.values.data());
  }
}

void GlConvolution::transform_psf(const Psf& psf, const Grid& grid) {
  // The PSF in float: the pad pass reads it, and the bright sum of any image later with this PSF.
  const std::vector<float> psf_values(psf.values.begin(), psf.values.end());
  write_buffer(kernel_.get(), kernel_bytes_, psf_values.size() * sizeof(float), psf_values.data());
  const GLuint pad_kernel = pad_kernel_program_.get();
  glUseProgram(pad_kernel);
  glUniform1i(glGetUniformLocation(pad_kernel, "uPaddedWidth"), grid.padded_width);
  glUniform1i(glGetUniformLocation(pad_kernel, "uPaddedHeight"), grid.padded_height);
  glUniform1i(glGetUniformLocation(pad_kernel, "uKernelSize"), grid.kernel_px);
  glUniform1i(glGetUniformLocation(pad_kernel, "uKernelLayers"), psf.channels);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->kernel.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, kernel_.get());
  glDispatchCompute(groups_of(grid.padded_width, kPadTile), groups_of(grid.padded_height, kPadTile), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  ffts_->kernel.transform(FftDirection::forward);
}

void GlConvolution::multiply_spectra(const Grid& grid) {
  const GLuint multiply = multiply_program_.get();
  glUseProgram(multiply);
  glUniform1ui(glGetUniformLocation(multiply, "uPaddedWidth"), static_cast<GLuint>(grid.padded_width));
  glUniform1ui(glGetUniformLocation(multiply, "uPaddedHeight"), static_cast<GLuint>(grid.padded_height));
  glUniform1ui(glGetUniformLocation(multiply, "uKernelChannels"), static_cast<GLuint>(grid.kernel_layers));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->image.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, ffts_->kernel.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ffts_->product.data());
  glDispatchCompute(std::min((static_cast<GLuint>(grid.layer) + kMultiplyGroup - 1) / kMultiplyGroup, kMaxMultiplyGroups), 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlConvolution::add_bright_pixels(const ImageSpectrum& scene, const Grid& grid) {
  const BrightPixels& bright = scene.bright;
  const int width = grid.width, height = grid.height, k = grid.kernel_px;
  const GLuint splat = splat_program_.get();
  glUseProgram(splat);
  glUniform1i(glGetUniformLocation(splat, "uWidth"), width);
  glUniform1i(glGetUniformLocation(splat, "uHeight"), height);
  glUniform1i(glGetUniformLocation(splat, "uPaddedWidth"), grid.padded_width);
  glUniform1i(glGetUniformLocation(splat, "uLayerSize"), static_cast<GLint>(grid.layer));
  glUniform1i(glGetUniformLocation(splat, "uKernelSize"), k);
  glUniform1i(glGetUniformLocation(splat, "uKernelLayers"), grid.kernel_layers);
  glUniform1i(glGetUniformLocation(splat, "uBrightCount"), static_cast<GLint>(bright.count()));
  // Only pixels within the PSF's reach of a bright pixel receive anything: the bright pixels'
  // bounding box grown by the reach: bright_splat.comp's offset pixel - bright + K/2 lies in
  // [0, K), so K/2 on the low side and K - 1 - K/2 on the high side.
  const int x0 = std::max(0, bright.x0 - k / 2), y0 = std::max(0, bright.y0 - k / 2);
  const int x1 = std::min(width - 1, bright.x1 + (k - 1 - k / 2));
  const int y1 = std::min(height - 1, bright.y1 + (k - 1 - k / 2));
  glUniform2i(glGetUniformLocation(splat, "uOrigin"), x0, y0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->product.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, bright_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, bright_values_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, kernel_.get());
  glDispatchCompute(groups_of(x1 - x0 + 1, kTile), groups_of(y1 - y0 + 1, kTile), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void GlConvolution::crop(const Grid& grid, std::size_t image_bytes) {
  if (result_bytes_ != image_bytes) {
    result_bytes_ = image_bytes;
    glNamedBufferData(result_.get(), static_cast<GLsizeiptr>(result_bytes_), nullptr, GL_DYNAMIC_READ);
  }
  const GLuint program = crop_program_.get();
  glUseProgram(program);
  set_grid_uniforms(program, grid.width, grid.height, grid.padded_width, grid.padded_height);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, ffts_->product.data());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, image_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, result_.get());
  glDispatchCompute(groups_of(grid.width, kPadTile), groups_of(grid.height, kPadTile), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
}

void GlConvolution::read_gpu_stages(GlConvolutionReport& report) const {
  std::vector<GLuint64> stamps_ns(timestamps_.size(), 0);
  for (std::size_t s = 0; s < timestamps_.size(); ++s)
    glGetQueryObjectui64v(timestamps_[s].get(), GL_QUERY_RESULT, &stamps_ns[s]);
  const auto seconds_between = [](GLuint64 from_ns, GLuint64 to_ns) {
    return to_ns > from_ns ? 1e-9 * static_cast<double>(to_ns - from_ns) : 0.0;
  };
  report.gpu_s = seconds_between(stamps_ns.front(), stamps_ns.back());
  for (std::size_t s = 0; s + 1 < stamps_ns.size(); ++s)
    report.gpu_stages_s.emplace_back(kStageNames[s], seconds_between(stamps_ns[s], stamps_ns[s + 1]));
}

ImageRGBA GlConvolution::convolve(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options,
                                  GlConvolutionReport* report) {
  ImageRGBA output(image.width_px, image.height_px);
  run(image, psf, options, report, &output);
  return output;
}

GLuint GlConvolution::convolve_on_gpu(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options,
                                      GlConvolutionReport* report) {
  run(image, psf, options, report, nullptr);
  // The result is read next by shaders (a storage buffer) or copied (glCopyNamedBufferSubData).
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  return result_.get();
}

void GlConvolution::run(const ImageRGBA& image, const Psf& psf, const GlConvolutionOptions& options,
                        GlConvolutionReport* report, ImageRGBA* output) {
  validate_psf(psf);
  const int width = image.width_px, height = image.height_px, k = psf.size_px;
  if (image.empty()) throw std::invalid_argument("GL convolution: the image is empty");
  const int padded_width = padded_fft_length(width + k - 1);
  const int padded_height = padded_fft_length(height + k - 1);
  if (padded_width == 0 || padded_height == 0)
    throw std::invalid_argument("GL convolution: image " + std::to_string(width) + " x " + std::to_string(height) +
                                " with a " + std::to_string(k) + " px PSF needs a padded grid above " +
                                std::to_string(kFftMaxLength));
  if (!ffts_ || ffts_->image.width() != padded_width || ffts_->image.height() != padded_height ||
      ffts_->kernel.layers() != packed_layers(psf.channels)) {
    ffts_ = std::make_unique<Ffts>(Ffts{GlFft(padded_width, padded_height, packed_layers(3)),
                                        GlFft(padded_width, padded_height, packed_layers(psf.channels)),
                                        GlFft(padded_width, padded_height, packed_layers(3))});
    kernel_ready_ = false;
    image_spectrum_.reset();
  }
  const std::size_t layer = static_cast<std::size_t>(padded_width) * padded_height;
  const Grid grid{width, height, padded_width, padded_height, k, psf.channels, layer};

  // The image's spectrum is kept while the same image comes again with the same split (a static
  // scene under dynamic glare: only the PSF changes from frame to frame).
  const bool image_cached = image_spectrum_ && same_split(image_spectrum_->options, options) &&
                            image_spectrum_->image.width_px == width && image_spectrum_->image.height_px == height &&
                            (options.image_token != 0 ? image_spectrum_->options.image_token == options.image_token
                                                      : image_spectrum_->image.rgba == image.rgba);
  std::unique_ptr<ImageSpectrum> fresh_spectrum;
  if (!image_cached) {
    fresh_spectrum = split_image(image, options);
    // The kept spectrum is overwritten below: it is kept again (as this image's) only once the
    // call has gone through.
    image_spectrum_.reset();
  }
  const ImageSpectrum& scene = image_cached ? *image_spectrum_ : *fresh_spectrum;
  GlConvolutionReport local_report;
  local_report.padded_width_px = padded_width;
  local_report.padded_height_px = padded_height;
  local_report.bright_threshold = scene.bright_threshold;
  local_report.bright_pixels = scene.bright.count();
  local_report.split = scene.split;
  local_report.image_spectrum_reused = image_cached;

  std::size_t stamp = 0;
  const auto stage_done = [&] { glQueryCounter(timestamps_[stamp++].get(), GL_TIMESTAMP); };
  stage_done();
  if (!image_cached) pad_image(image, scene, grid);
  stage_done();

  // The PSF's spectrum is kept while the same PSF comes again on the same padded grid (static
  // glare, successive frames).
  const bool kernel_cached = kernel_ready_ && cached_psf_size_ == k && cached_psf_values_ == psf.values;
  if (!kernel_cached) {
    transform_psf(psf, grid);
    // Kept as this PSF's once the call has gone through (below).
    kernel_ready_ = false;
  }
  local_report.psf_spectrum_reused = kernel_cached;
  stage_done();

  if (!image_cached) ffts_->image.transform(FftDirection::forward);
  stage_done();
  multiply_spectra(grid);
  stage_done();
  ffts_->product.transform(FftDirection::inverse);
  stage_done();
  if (scene.split) add_bright_pixels(scene, grid);
  stage_done();
  crop(grid, image.rgba.size() * sizeof(float));
  stage_done();
  if (output != nullptr)
    read_back_buffer(result_.get(), 0, output->rgba.size() * sizeof(float), output->rgba.data(), ReadBackKind::frame);
  stage_done();
  check_gl_error("GL convolution");
  if (!kernel_cached) {
    cached_psf_size_ = k;
    cached_psf_values_ = psf.values;
    kernel_ready_ = true;
  }
  if (!image_cached) image_spectrum_ = std::move(fresh_spectrum);
  read_gpu_stages(local_report);
  if (report != nullptr) *report = local_report;
}

}  // namespace glarelab::gl
