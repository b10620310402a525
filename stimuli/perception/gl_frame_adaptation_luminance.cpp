#include "stimuli/perception/gl_frame_adaptation_luminance.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/gl/read_back.h"
#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

void validate(double gaze_x, double gaze_y, const AdaptationWeighting& weighting) {
  if (!std::isfinite(gaze_x) || !std::isfinite(gaze_y))
    throw std::invalid_argument("perception adaptation: gaze must be finite (got " + std::to_string(gaze_x) + ", " +
                                std::to_string(gaze_y) + ")");
  if (!std::isfinite(weighting.gaze_sigma_frame_widths) || weighting.gaze_sigma_frame_widths <= 0.0)
    throw std::invalid_argument("perception adaptation: gaze_sigma_frame_widths must be finite and > 0 (got " +
                                std::to_string(weighting.gaze_sigma_frame_widths) + ")");
  const int size = weighting.resampled_size_px, top = weighting.top_level_size_px;
  if (top < 1 || size < top || size > 4096 || size % top != 0 || ((size / top) & (size / top - 1)) != 0)
    throw std::invalid_argument(
        "perception adaptation: resampled_size_px (at most 4096) / top_level_size_px must be a power of two");
}

// The pixel index nearest a normalised coordinate along an axis of n pixels.
int nearest_pixel(double coordinate, int n) {
  return static_cast<int>(std::clamp(std::floor(coordinate * n), 0.0, static_cast<double>(n - 1)));
}

}  // namespace

GlFrameAdaptationLuminance::GlFrameAdaptationLuminance()
    : resample_program_(build_program({"stimuli/perception/shaders/adaptation_resample.comp"})),
      pyramid_program_(build_program({"stimuli/perception/shaders/adaptation_pyramid.comp"})),
      level_a_(create_buffer()),
      level_b_(create_buffer()) {}

double GlFrameAdaptationLuminance::luminance_cd_m2(const GlFrameBuffer& frame, double gaze_x, double gaze_y,
                                                   const AdaptationWeighting& weighting) {
  validate(gaze_x, gaze_y, weighting);
  const int width = frame.width_px(), height = frame.height_px();
  const int size = weighting.resampled_size_px, top = weighting.top_level_size_px;
  if (size * size > allocated_cells_) {
    for (Buffer* level : {&level_a_, &level_b_})
      glNamedBufferData(level->get(), static_cast<GLsizeiptr>(size) * size * 2 * sizeof(float), nullptr, GL_DYNAMIC_COPY);
    allocated_cells_ = size * size;
  }

  // The Gaussian relative to its value at the pixel nearest the gaze (adaptation_resample.comp).
  // Where that value itself underflows in double, every weight of the reference is 0 and it falls
  // back to the plain mean (frame_adaptation_luminance.cpp); the same here.
  const double sigma = weighting.gaze_sigma_frame_widths;
  const int nearest_x = nearest_pixel(gaze_x, width), nearest_y = nearest_pixel(gaze_y, height);
  const double offset_x = (nearest_x + 0.5) / width - gaze_x;
  const double offset_y = ((nearest_y + 0.5) / height - gaze_y) * static_cast<double>(height) / width;
  const double largest_weight = std::exp(-(offset_x * offset_x + offset_y * offset_y) / (2.0 * sigma * sigma));
  const bool uniform = !(largest_weight >= DBL_MIN);

  const GLuint resample = resample_program_.get();
  glUseProgram(resample);
  glUniform1i(glGetUniformLocation(resample, "uWidth"), width);
  glUniform1i(glGetUniformLocation(resample, "uHeight"), height);
  glUniform1i(glGetUniformLocation(resample, "uSize"), size);
  glUniform2i(glGetUniformLocation(resample, "uNearest"), nearest_x, nearest_y);
  glUniform2f(glGetUniformLocation(resample, "uNearestOffset"), static_cast<float>(offset_x),
              static_cast<float>(offset_y));
  glUniform1f(glGetUniformLocation(resample, "uInvTwoSigma2"),
              uniform ? 0.0f : static_cast<float>(1.0 / (2.0 * sigma * sigma)));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, frame.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, level_a_.get());
  dispatch_per_pixel(size, size);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  const GLuint pyramid = pyramid_program_.get();
  glUseProgram(pyramid);
  const GLint size_location = glGetUniformLocation(pyramid, "uSize");
  GLuint source = level_a_.get(), target = level_b_.get();
  for (int level = size; level > top; level /= 2) {
    glUniform1i(size_location, level);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, source);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, target);
    dispatch_per_pixel(level / 2, level / 2);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    std::swap(source, target);
  }
  glUseProgram(0);
  check_gl_error("perception adaptation");

  std::vector<float> cells(static_cast<std::size_t>(top) * top * 2);
  // The pyramid's top cells: a reduction of a few values, not the frame.
  read_back_buffer(source, 0, cells.size() * sizeof(float), cells.data(), ReadBackKind::reduction);
  double weighted = 0.0, weights = 0.0;
  for (std::size_t i = 0; i < cells.size(); i += 2) {
    weighted += cells[i];
    weights += cells[i + 1];
  }
  if (!(weights > 0.0)) throw std::runtime_error("perception adaptation: the GL weights summed to " + std::to_string(weights));
  return weighted / weights;
}

}  // namespace glarelab::gl
