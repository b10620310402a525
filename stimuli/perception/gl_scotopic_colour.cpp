#include "stimuli/perception/gl_scotopic_colour.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "core/gl/shader_program.h"
#include "stimuli/perception/scotopic_colour.h"

namespace glarelab::gl {

GlScotopicColour::GlScotopicColour() : program_(build_program({"stimuli/perception/shaders/scotopic_colour.comp"})) {}

void GlScotopicColour::apply(const GlFrameBuffer& input, double rod_sensitivity, const ScotopicSettings& settings,
                             GlFrameBuffer& output) {
  validate_scotopic_settings(settings);
  if (!std::isfinite(rod_sensitivity) || rod_sensitivity < 0.0 || rod_sensitivity > 1.0)
    throw std::invalid_argument("perception scotopic: the rod sensitivity must be in [0, 1] (got " +
                                std::to_string(rod_sensitivity) + ")");
  if (output.width_px() != input.width_px() || output.height_px() != input.height_px())
    throw std::invalid_argument("perception scotopic: the GL output must have the input's size");
  const GLuint program = program_.get();
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "uWidth"), input.width_px());
  glUniform1i(glGetUniformLocation(program, "uHeight"), input.height_px());
  glUniform1i(glGetUniformLocation(program, "uForm"), settings.form == ScotopicForm::luidolt_tint ? 0 : 1);
  glUniform1f(glGetUniformLocation(program, "uRod"), static_cast<float>(rod_sensitivity));
  glUniform1f(glGetUniformLocation(program, "uOneMinusRod"), static_cast<float>(1.0 - rod_sensitivity));
  glUniform1f(glGetUniformLocation(program, "uKeep"),
              static_cast<float>(1.0 - settings.spencer_saturation_reduction * rod_sensitivity));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, input.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, output.buffer());
  dispatch_per_pixel(input.width_px(), input.height_px());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  check_gl_error("perception scotopic");
}

}  // namespace glarelab::gl
