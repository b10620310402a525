#include "stimuli/perception/gl_acuity_loss.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/gl/shader_program.h"
#include "stimuli/perception/acuity_loss.h"

namespace glarelab::gl {
namespace {

// Rec.709's D65 white, the rows of lab_colour.cpp's kRgbToXyz summed (Y = 1).
constexpr double kWhiteX = 0.41239079926595948 + 0.35758433938387796 + 0.18048078840183429;
constexpr double kWhiteY = 0.21263900587151036 + 0.71516867876775593 + 0.07219231536073372;
constexpr double kWhiteZ = 0.01933081871559185 + 0.11919477979462599 + 0.95053215224966058;
constexpr double kDelta = 6.0 / 29.0;

}  // namespace

GlAcuityLoss::GlAcuityLoss()
    : to_lab_program_(build_program({"stimuli/perception/shaders/acuity_to_lab.comp"})),
      blur_program_(build_program({"stimuli/perception/shaders/acuity_blur.comp"})),
      lab_(create_buffer()),
      lightness_(create_buffer()) {}

void GlAcuityLoss::apply(const GlFrameBuffer& input, const AcuitySettings& settings, double pixels_per_degree,
                         GlFrameBuffer& output) {
  validate_acuity_settings(settings);
  if (!std::isfinite(pixels_per_degree) || pixels_per_degree <= 0.0)
    throw std::invalid_argument("perception acuity: pixels per degree must be finite and > 0 (got " +
                                std::to_string(pixels_per_degree) + ")");
  const int width = input.width_px(), height = input.height_px();
  if (output.width_px() != width || output.height_px() != height || output.buffer() == input.buffer())
    throw std::invalid_argument("perception acuity: the GL output must be another buffer of the input's size");
  const long long pixels = static_cast<long long>(width) * height;
  if (pixels > allocated_pixels_) {
    glNamedBufferData(lab_.get(), static_cast<GLsizeiptr>(pixels * 4 * sizeof(float)), nullptr, GL_DYNAMIC_COPY);
    glNamedBufferData(lightness_.get(), static_cast<GLsizeiptr>(pixels * sizeof(float)), nullptr, GL_DYNAMIC_COPY);
    allocated_pixels_ = pixels;
  }
  const double scale = settings.reference_white_cd_m2 / kWhiteY;  // Y_n; X_n, Z_n in proportion (lab_colour.cpp)

  const GLuint to_lab = to_lab_program_.get();
  glUseProgram(to_lab);
  glUniform1i(glGetUniformLocation(to_lab, "uWidth"), width);
  glUniform1i(glGetUniformLocation(to_lab, "uHeight"), height);
  glUniform3f(glGetUniformLocation(to_lab, "uInvWhite"), static_cast<float>(1.0 / (kWhiteX * scale)),
              static_cast<float>(1.0 / (kWhiteY * scale)), static_cast<float>(1.0 / (kWhiteZ * scale)));
  glUniform1d(glGetUniformLocation(to_lab, "uInvWhiteY"), 1.0 / (kWhiteY * scale));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, input.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, lab_.get());
  dispatch_per_pixel(width, height);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  const GLuint blur = blur_program_.get();
  glUseProgram(blur);
  glUniform1i(glGetUniformLocation(blur, "uWidth"), width);
  glUniform1i(glGetUniformLocation(blur, "uHeight"), height);
  glUniform1i(glGetUniformLocation(blur, "uSecondPassFiltered"),
              settings.second_pass == SecondPassSigma::filtered_lightness ? 1 : 0);
  glUniform1i(glGetUniformLocation(blur, "uLuidoltLinear"),
              settings.sigma_form == AcuitySigmaForm::luidolt_linear ? 1 : 0);
  glUniform1f(glGetUniformLocation(blur, "uMaxSigma"), static_cast<float>(settings.max_sigma_px));
  // Eq. 5.15: sigma_px = ppd / (1.86 sqrt(2) R).
  glUniform1f(glGetUniformLocation(blur, "uSigmaNumerator"),
              static_cast<float>(pixels_per_degree / (1.86 * std::sqrt(2.0))));
  glUniform1f(glGetUniformLocation(blur, "uLuminancePerLightness"),
              static_cast<float>(settings.reference_white_cd_m2 * 3.0 * kDelta * kDelta / 116.0));
  // Eq. 5.14's constant with the whole multiples of pi / 4 of atan taken out (acuity_blur.comp).
  float resolvable_base[5];
  for (int k = -2; k <= 2; ++k) resolvable_base[k + 2] = static_cast<float>(25.72 + 17.25 * k * std::numbers::pi / 4.0);
  glUniform1fv(glGetUniformLocation(blur, "uResolvableBase"), 5, resolvable_base);
  glUniform3f(glGetUniformLocation(blur, "uWhite"), static_cast<float>(kWhiteX * scale),
              static_cast<float>(kWhiteY * scale), static_cast<float>(kWhiteZ * scale));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, lab_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, lightness_.get());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, input.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, output.buffer());
  const GLint pass = glGetUniformLocation(blur, "uPass");
  glUniform1i(pass, 0);
  dispatch_per_pixel(width, height);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUniform1i(pass, 1);
  dispatch_per_pixel(width, height);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  check_gl_error("perception acuity");
}

}  // namespace glarelab::gl
