#include "runner/timing/timing_pattern.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/gl/shader_program.h"

namespace glarelab {

TimingPattern parse_timing_pattern(const std::string& name) {
  if (name == "flicker") return TimingPattern::flicker;
  if (name == "tearing") return TimingPattern::tearing;
  throw std::invalid_argument("timing-test: unknown pattern '" + name + "' (flicker or tearing)");
}

const char* to_string(TimingPattern pattern) { return pattern == TimingPattern::flicker ? "flicker" : "tearing"; }

std::vector<std::string> timing_pattern_names() { return {"flicker", "tearing"}; }

std::vector<int> tearing_bar_lefts_px(int width_px, long frame_index) {
  const double period_px = kTearingPeriodFraction * width_px;
  const double bar_px = kTearingBarFraction * width_px;
  // The offset wraps every period: the pattern repeats every 8 frames.
  const double offset_px = std::fmod(static_cast<double>(frame_index) * kTearingStepFraction * width_px, period_px);
  std::vector<int> lefts;
  for (double left = offset_px - period_px; left < width_px; left += period_px)
    if (left + bar_px > 0.0) lefts.push_back(static_cast<int>(std::lround(left)));
  return lefts;
}

void draw_timing_pattern(TimingPattern pattern, long frame_index, int width_px, int height_px, unsigned framebuffer) {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, width_px, height_px);
  const float background = pattern == TimingPattern::flicker && frame_index % 2 == 0 ? 1.0f : 0.0f;
  glClearColor(background, background, background, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  if (pattern == TimingPattern::tearing) {
    const int bar_px = std::max(1, static_cast<int>(std::lround(kTearingBarFraction * width_px)));
    glEnable(GL_SCISSOR_TEST);
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    for (const int left : tearing_bar_lefts_px(width_px, frame_index)) {
      const int x0 = std::max(0, left);
      const int x1 = std::min(width_px, left + bar_px);
      if (x1 <= x0) continue;
      glScissor(x0, 0, x1 - x0, height_px);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    glDisable(GL_SCISSOR_TEST);
  }
  gl::check_gl_error("timing-test: drawing the pattern");
}

}  // namespace glarelab
