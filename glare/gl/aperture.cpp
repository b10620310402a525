#include "glare/gl/aperture.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

constexpr GLuint kLocalSize = 8;  // local_size_x/y of both aperture shaders

Texture r32f_texture(int size) {
  Texture texture = create_texture(GL_TEXTURE_2D);
  glTextureStorage2D(texture.get(), 1, GL_R32F, size, size);
  glTextureParameteri(texture.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return texture;
}

// Replaces the contents of a mutable storage buffer; never empty, since a zero-size buffer cannot
// be bound (the shader reads no element past its count uniform, so four zeros stand in for none).
template <typename Value>
void fill(const Buffer& buffer, const std::vector<Value>& values) {
  static const std::vector<Value> zeros_for_empty(4, Value{0});
  const std::vector<Value>& data = values.empty() ? zeros_for_empty : values;
  glNamedBufferData(buffer.get(), static_cast<GLsizeiptr>(data.size() * sizeof(Value)), data.data(), GL_DYNAMIC_DRAW);
}

GLuint groups(int extent) { return (static_cast<GLuint>(extent) + kLocalSize - 1) / kLocalSize; }

}  // namespace

int bins_across_for(int samples_across) { return std::min(64, samples_across); }

double axis_samples(int samples_across, int supersampling) { return 0.5 * (samples_across + supersampling); }

std::vector<std::uint32_t> bin_primitives(const ApertureGeometry& geometry, int samples_across, double aperture_width_mm,
                                          int supersampling) {
  const int bins_across = bins_across_for(samples_across);
  const double h = aperture_width_mm / samples_across;
  const double axis = axis_samples(samples_across, supersampling);
  // Sample a (column, or row) lies in bin a B / S (integer division, as in the shader). Column of
  // x: a = x / h + c - 0.5; row of y: b = c - 0.5 - y / h. The range is grown by one sample so
  // float rounding in the shader cannot put a covered sample outside it.
  const auto bin_range = [&](double lo_mm, double hi_mm, bool rows, int& first, int& last) {
    const double a0 = (rows ? axis - 0.5 - hi_mm / h : lo_mm / h + axis - 0.5) - 1.0;
    const double a1 = (rows ? axis - 0.5 - lo_mm / h : hi_mm / h + axis - 0.5) + 1.0;
    const double first_sample = std::max(std::ceil(a0), 0.0);
    const double last_sample = std::min(std::floor(a1), samples_across - 1.0);
    if (!(first_sample <= last_sample)) return false;
    first = static_cast<int>(static_cast<long long>(first_sample) * bins_across / samples_across);
    last = static_cast<int>(static_cast<long long>(last_sample) * bins_across / samples_across);
    return true;
  };
  std::vector<std::vector<std::uint32_t>> lists(static_cast<std::size_t>(bins_across) * bins_across);
  const auto add = [&](double x0, double y0, double x1, double y1, std::uint32_t code) {
    int c0 = 0, c1 = 0, r0 = 0, r1 = 0;
    if (!bin_range(x0, x1, false, c0, c1) || !bin_range(y0, y1, true, r0, r1)) return;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) lists[static_cast<std::size_t>(r) * bins_across + c].push_back(code);
  };
  for (std::size_t i = 0; i < geometry.discs.size(); ++i) {
    const ApertureDisc& d = geometry.discs[i];
    add(d.centre_x_mm - d.radius_mm, d.centre_y_mm - d.radius_mm, d.centre_x_mm + d.radius_mm,
        d.centre_y_mm + d.radius_mm, static_cast<std::uint32_t>(i));
  }
  for (std::size_t i = 0; i < geometry.lines.size(); ++i) {
    const ApertureLine& l = geometry.lines[i];
    const double w = 0.5 * l.width_mm;
    add(std::min(l.x0_mm, l.x1_mm) - w, std::min(l.y0_mm, l.y1_mm) - w, std::max(l.x0_mm, l.x1_mm) + w,
        std::max(l.y0_mm, l.y1_mm) + w, static_cast<std::uint32_t>(i) | 0x80000000u);
  }
  std::vector<std::uint32_t> packed{0u};
  for (const auto& list : lists) packed.push_back(packed.back() + static_cast<std::uint32_t>(list.size()));
  for (const auto& list : lists) packed.insert(packed.end(), list.begin(), list.end());
  return packed;
}

GlAperture::GlAperture(int size_px, double aperture_width_mm, int supersampling)
    : size_px_(size_px), aperture_width_mm_(aperture_width_mm), supersampling_(supersampling) {
  if (size_px < 16 || size_px > 4096)
    throw std::invalid_argument("GL aperture: grid size " + std::to_string(size_px) + " is not 16..4096");
  if (!(aperture_width_mm > 0.0) || !std::isfinite(aperture_width_mm))
    throw std::invalid_argument("GL aperture: aperture width " + std::to_string(aperture_width_mm) + " mm is not positive");
  if (supersampling < 2 || supersampling > 8)
    throw std::invalid_argument("GL aperture: supersampling " + std::to_string(supersampling) +
                                " is not 2..8 (Ritschel et al. 2009, section 5: at least 2 x 2)");
  GLint max_texture_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size);
  if (size_px * supersampling > max_texture_size)
    throw std::invalid_argument("GL aperture: supersampled grid " + std::to_string(size_px * supersampling) +
                                " exceeds GL_MAX_TEXTURE_SIZE " + std::to_string(max_texture_size));
  draw_program_ = build_program({"glare/shaders/aperture_supersample.comp"});
  downsample_program_ = build_program({"glare/shaders/aperture_downsample.comp"});
  samples_ = r32f_texture(size_px * supersampling);
  aperture_ = r32f_texture(size_px);
  discs_ = create_buffer();
  lines_ = create_buffer();
  polygons_ = create_buffer();
  vertices_ = create_buffer();
  bin_offsets_ = create_buffer();
  bin_items_ = create_buffer();
  check_gl_error("GL aperture: creating textures and programs");
}

void GlAperture::draw(const ApertureGeometry& geometry) {
  std::vector<float> discs, lines, polygons, vertices;
  for (const ApertureDisc& d : geometry.discs)
    discs.insert(discs.end(), {static_cast<float>(d.centre_x_mm), static_cast<float>(d.centre_y_mm),
                               static_cast<float>(d.radius_mm), static_cast<float>(d.transmittance)});
  for (const ApertureLine& l : geometry.lines)
    lines.insert(lines.end(), {static_cast<float>(l.x0_mm), static_cast<float>(l.y0_mm), static_cast<float>(l.x1_mm),
                               static_cast<float>(l.y1_mm), static_cast<float>(0.5 * l.width_mm),
                               static_cast<float>(l.transmittance), 0.0f, 0.0f});
  std::vector<std::uint32_t> polygon_words;
  for (const AperturePolygon& polygon : geometry.polygons) {
    if (polygon.vertices_mm.size() % 2 != 0)
      throw std::invalid_argument("GL aperture: a polygon has an odd number of coordinates (" +
                                  std::to_string(polygon.vertices_mm.size()) + ")");
    const float transmittance = static_cast<float>(polygon.transmittance);
    std::uint32_t transmittance_bits = 0;
    static_assert(sizeof transmittance_bits == sizeof transmittance);
    std::memcpy(&transmittance_bits, &transmittance, sizeof transmittance);
    polygon_words.insert(polygon_words.end(), {static_cast<std::uint32_t>(vertices.size() / 2),
                                               static_cast<std::uint32_t>(polygon.vertices_mm.size() / 2),
                                               transmittance_bits, 0u});
    for (const double coordinate : polygon.vertices_mm) vertices.push_back(static_cast<float>(coordinate));
  }
  const std::vector<std::uint32_t> bins = bin_primitives(geometry, size_px_ * supersampling_, aperture_width_mm_, supersampling_);
  const int bins_across = bins_across_for(size_px_ * supersampling_);
  const std::vector<std::uint32_t> offsets(bins.begin(), bins.begin() + bins_across * bins_across + 1);
  const std::vector<std::uint32_t> items(bins.begin() + bins_across * bins_across + 1, bins.end());
  fill(bin_offsets_, offsets);
  fill(bin_items_, items);
  polygons.resize(polygon_words.size());
  if (!polygon_words.empty()) std::memcpy(polygons.data(), polygon_words.data(), polygon_words.size() * sizeof(float));
  fill(discs_, discs);
  fill(lines_, lines);
  fill(polygons_, polygons);
  fill(vertices_, vertices);

  const int across = size_px_ * supersampling_;
  const GLuint draw = draw_program_.get();
  glUseProgram(draw);
  glUniform1i(glGetUniformLocation(draw, "uSamplesAcross"), across);
  glUniform1f(glGetUniformLocation(draw, "uSampleMm"), static_cast<float>(aperture_width_mm_ / across));
  glUniform1f(glGetUniformLocation(draw, "uAxisSamples"), static_cast<float>(axis_samples(across, supersampling_)));
  glUniform1f(glGetUniformLocation(draw, "uPupilRadiusMm"), static_cast<float>(0.5 * geometry.pupil_diameter_mm));
  glUniform1i(glGetUniformLocation(draw, "uBinsAcross"), bins_across);
  glUniform1i(glGetUniformLocation(draw, "uPolygonCount"), static_cast<GLint>(geometry.polygons.size()));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, discs_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, lines_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, polygons_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, vertices_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, bin_offsets_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, bin_items_.get());
  glBindImageTexture(0, samples_.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(groups(across), groups(across), 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);

  const GLuint downsample = downsample_program_.get();
  glUseProgram(downsample);
  glUniform1i(glGetUniformLocation(downsample, "uSize"), size_px_);
  glUniform1i(glGetUniformLocation(downsample, "uSupersampling"), supersampling_);
  glBindImageTexture(0, samples_.get(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(1, aperture_.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glDispatchCompute(groups(size_px_), groups(size_px_), 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  check_gl_error("GL aperture: draw");
}

std::vector<float> read_r32f(GLuint texture, int width, int height) {
  std::vector<float> values(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  read_back_texture(texture, GL_RED, GL_FLOAT, values.size() * sizeof(float), values.data(), ReadBackKind::kernel);
  check_gl_error("GL aperture: reading an R32F texture");
  return values;
}

std::vector<float> GlAperture::read() const { return read_r32f(aperture_.get(), size_px_, size_px_); }
std::vector<float> GlAperture::read_supersampled() const {
  return read_r32f(samples_.get(), size_px_ * supersampling_, size_px_ * supersampling_);
}

}  // namespace glarelab::gl
