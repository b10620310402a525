// The double-adjustment inputs (runner/session/adjustment_keys.h): keys, wheel clicks and device
// buttons to log10 steps, with the coarse/fine mode, against the table in the header.
#include <gtest/gtest.h>

#include "runner/session/adjustment_keys.h"

namespace glarelab {
namespace {

TEST(AdjustmentInput, KeysWheelAndButtonsStepInCoarseAndFineModes) {
  AdjustmentSpec spec;
  spec.coarse_step_log10 = 0.1;
  spec.fine_step_log10 = 0.01;
  AdjustmentControl control(spec);
  struct Case {
    const char* input;
    bool shift;
    AdjustmentEffect effect;
    double log10_step;
    bool fine_mode_after;
  };
  const Case cases[] = {
      {"up", false, AdjustmentEffect::step, 0.1, false},
      {"wheel_up", false, AdjustmentEffect::step, 0.1, false},
      {"wheel_down", true, AdjustmentEffect::step, -0.01, false},  // Shift: fine
      {"down", true, AdjustmentEffect::step, -0.01, false},
      {"right", false, AdjustmentEffect::step, 0.01, false},
      {"left", false, AdjustmentEffect::step, -0.01, false},
      {"f", false, AdjustmentEffect::mode_change, 0.0, true},
      {"wheel_up", false, AdjustmentEffect::step, 0.01, true},     // fine mode
      {"up", false, AdjustmentEffect::step, 0.01, true},
      {"down", false, AdjustmentEffect::step, -0.01, true},
      {"coarse_up", false, AdjustmentEffect::step, 0.1, true},     // coarse whatever the mode
      {"coarse_down", true, AdjustmentEffect::step, -0.1, true},
      {"fine_up", false, AdjustmentEffect::step, 0.01, true},
      {"fine_down", false, AdjustmentEffect::step, -0.01, true},
      {"fine_mode", false, AdjustmentEffect::mode_change, 0.0, false},  // the button switches back
      {"wheel_down", false, AdjustmentEffect::step, -0.1, false},
      {"a", false, AdjustmentEffect::none, 0.0, false},
      {"escape", false, AdjustmentEffect::none, 0.0, false},
      {"enter", false, AdjustmentEffect::accept, 0.0, false},
      {"space", false, AdjustmentEffect::accept, 0.0, false},
      {"accept", false, AdjustmentEffect::accept, 0.0, false},
  };
  for (const Case& c : cases) {
    const AdjustmentStep step = control.apply(c.input, c.shift);
    EXPECT_EQ(step.effect, c.effect) << c.input;
    EXPECT_EQ(step.log10_step, c.log10_step) << c.input;
    EXPECT_EQ(control.fine_mode(), c.fine_mode_after) << c.input;
  }
}

}  // namespace
}  // namespace glarelab
