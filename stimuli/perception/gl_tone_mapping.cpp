#include "stimuli/perception/gl_tone_mapping.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "core/gl/shader_program.h"
#include "stimuli/perception/tone_mapping.h"

namespace glarelab::gl {

GlToneMapping::GlToneMapping() : program_(build_program({"stimuli/perception/shaders/tone_mapping.comp"})) {}

void GlToneMapping::apply(const GlFrameBuffer& input, double adapted_luminance_cd_m2,
                          const ToneMappingSettings& settings, double peak_luminance_cd_m2, GlFrameBuffer& output) {
  validate_tone_mapping_inputs(settings, adapted_luminance_cd_m2, peak_luminance_cd_m2);
  if (output.width_px() != input.width_px() || output.height_px() != input.height_px())
    throw std::invalid_argument("perception tone mapping: the GL output must have the input's size");
  const GLuint program = program_.get();
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "uWidth"), input.width_px());
  glUniform1i(glGetUniformLocation(program, "uHeight"), input.height_px());
  const int curve = settings.curve == ToneCurve::aces_narkowicz ? 0 : settings.curve == ToneCurve::aces_hill ? 1 : 2;
  glUniform1i(glGetUniformLocation(program, "uCurve"), curve);
  glUniform1f(glGetUniformLocation(program, "uExposure"),
              static_cast<float>(tone_mapping_exposure_per_cd_m2(adapted_luminance_cd_m2, settings)));
  glUniform1f(glGetUniformLocation(program, "uPeak"), static_cast<float>(peak_luminance_cd_m2));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, input.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, output.buffer());
  dispatch_per_pixel(input.width_px(), input.height_px());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  check_gl_error("perception tone mapping");
}

}  // namespace glarelab::gl
