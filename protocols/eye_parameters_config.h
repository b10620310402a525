#pragma once
// Reading the experiment file's [glare.eye] table into the eye model's parameters
// (glare/eye/eye_parameters.h; docs/EXPERIMENT_FILES.md, "[glare.eye]"): every field of the dynamic
// eye of Ritschel et al. 2009 that a study could set, under the field's own name (units in the
// names), each within stated bounds. The mode, the static instant and the field luminance before
// the first frame are not keys here: [glare] mode and static_time_s (and the condition column
// "glare") choose the first two, and the session gives the eye each frame's luminance.
#include <span>
#include <string_view>

#include <toml++/toml.h>

#include "glare/eye/eye_parameters.h"

namespace glarelab {

class TableReader;

// One key of [glare.eye]: the field it sets (a number or a count, never both) and its bounds,
// [minimum, maximum], or (minimum, maximum] when minimum_excluded. The bounds are what a human eye
// (or a deliberately exaggerated one in a study of its effect) can be; beyond them a value is a
// typo. Cross-field rules (pupil_min below pupil_max, the lids' order, the vitreous' Euler step,
// the gratings fitting in the lens) are glare/eye/eye_parameters.cpp's validate(), reported at the
// key it names.
struct EyeParameterKey {
  std::string_view key;
  double EyeParameters::*number = nullptr;
  int EyeParameters::*count = nullptr;
  double minimum = 0.0;
  double maximum = 0.0;
  bool minimum_excluded = false;
  std::string_view unit;  // printed after the bounds in a refusal ("mm", "s", "" for a count)
};

// Every key, in the order of the struct (and of docs/EXPERIMENT_FILES.md's table).
std::span<const EyeParameterKey> eye_parameter_keys();

// [glare.eye] from the [glare] table's reader (which it marks consumed), if present, over
// `parameters` (the defaults): ConfigError at file:line:column naming the key for a value of the
// wrong type, out of its bounds, breaking a cross-field rule, or an unknown key.
void read_glare_eye(TableReader& glare, EyeParameters& parameters);

// The table resolved_config_toml writes inside [glare] (every key explicit).
toml::table glare_eye_toml(const EyeParameters& parameters);

}  // namespace glarelab
