#pragma once
// Keys of the double-adjustment task (Yoshida 2008; Ritschel 2009, 6.1). Both comparison spots
// move together, each from its own random start: up/down change them by the coarse log step,
// right/left by the fine one; Enter or Space accepts the settings.
#include <optional>
#include <string>

#include "protocols/experiment.h"

namespace glarelab {

// The factor a key multiplies both settings by, or nothing for keys that do not adjust.
std::optional<double> adjustment_factor(const std::string& key, const AdjustmentSpec& spec);
bool accepts_adjustment(const std::string& key);
std::string describe_adjustment_keys(const AdjustmentSpec& spec);

}  // namespace glarelab
