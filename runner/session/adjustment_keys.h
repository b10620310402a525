#pragma once
// Inputs of the double-adjustment task (Yoshida 2008; Ritschel 2009, 6.1): the one place that maps
// keys, wheel clicks and response-device buttons to log10 steps. Both comparison spots move
// together, each from its own random start, by whole coarse or fine steps:
//
//   input                                    step
//   key up, wheel up, button "up"            + coarse (+ fine in fine mode or with Shift held)
//   key down, wheel down, button "down"      - coarse (- fine in fine mode or with Shift held)
//   button "coarse_up" / "coarse_down"       +/- coarse, whatever the mode
//   key right, button "fine_up"              + fine, whatever the mode
//   key left, button "fine_down"             - fine, whatever the mode
//   key f, button "fine_mode"                switches fine mode on or off
//   key enter or space, button "accept"      accepts the settings
//
// A setting is start * 10^(sum of the steps taken), so it is exactly the start times a whole
// number of coarse and fine steps.
#include <optional>
#include <string>

#include "protocols/experiment.h"

namespace glarelab {

enum class AdjustmentEffect {
  none,         // the input does not adjust (logged as ignored by the session)
  step,         // log10_step applies
  accept,       // the settings are the answer
  mode_change,  // fine mode switched (fine_mode() says to which)
};

struct AdjustmentStep {
  AdjustmentEffect effect = AdjustmentEffect::none;
  double log10_step = 0.0;
};

class AdjustmentControl {
 public:
  explicit AdjustmentControl(const AdjustmentSpec& spec) : spec_(spec) {}
  // `input`: a key name, a button name or "wheel_up"/"wheel_down"; `shift`: Shift held with it.
  AdjustmentStep apply(const std::string& input, bool shift);
  bool fine_mode() const { return fine_mode_; }

 private:
  AdjustmentSpec spec_;
  bool fine_mode_ = false;
};

// The factor an input multiplies both settings by in coarse mode without Shift, or nothing for
// inputs that do not step.
std::optional<double> adjustment_factor(const std::string& input, const AdjustmentSpec& spec);
bool accepts_adjustment(const std::string& input);
std::string describe_adjustment_keys(const AdjustmentSpec& spec);

}  // namespace glarelab
