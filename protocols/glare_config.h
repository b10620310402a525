#pragma once
// Reading the [glare] table of an experiment file into glare's GlareSpec (glare/glare_spec.h), and
// the per-condition glare mode (column "glare" of the condition table): which of Ritschel et al.
// 2009's conditions -- dynamic eye, static (frozen) eye, control (no glare) -- each condition shows
// (docs/EXPERIMENT_FILES.md).
#include <optional>
#include <string>
#include <utility>

#include <toml++/toml.h>

#include "glare/glare_spec.h"

namespace glarelab {

class TableReader;
struct ConditionRow;

// Reads [glare] if present (strictly: unknown keys are errors). `top` is the document root.
GlareSpec read_glare_section(TableReader& top);
// The table resolved_config_toml writes (every key explicit).
toml::table glare_section_toml(const GlareSpec& spec);
// The mode of one condition: its "glare" column, else spec.mode. ConfigError (at the row) for an
// unknown mode name.
GlareMode glare_mode_for(const GlareSpec& spec, const ConditionRow& row);
// The glare model of one condition: its "glare_model" column (ritschel, spencer, cie, hybrid), else
// spec.model. ConfigError (at the row) for an unknown name.
GlareModel glare_model_for(const GlareSpec& spec, const ConditionRow& row);
// The gain on the glare of one condition: its "glare_gain" column, else 1. The frame shown is
// frame + gain (glared - frame), negative values clipped to 0 (Spencer 1995, section 4: a series of
// glare strengths from barely blurred to implausible). ConfigError (at the row) for a value that
// is not a number in [0, kMaxGlareGain].
inline constexpr double kMaxGlareGain = 1000.0;
double glare_gain_for(const ConditionRow& row);
// Forced choice with a glare mode per side (Ritschel et al. 2009, section 6.1): the row's glare_a
// and glare_b columns (the modes shown with scene_a and scene_b), or nothing when the row has
// neither. ConfigError (at the row) for an unknown mode, for only one of the two columns, or for
// a row that also has a 'glare' column.
std::optional<std::pair<GlareMode, GlareMode>> position_glare_modes(const ConditionRow& row);

}  // namespace glarelab
