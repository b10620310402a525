#pragma once
// Reading the [perception] table of an experiment file into the perception stages' settings
// (core/perception_settings.h; Luidolt 2020, Fig. 6.1: adaptation -> glare -> acuity -> tone
// mapping -> scotopic colour), and the per-condition column "perception" that switches stages
// for a row, so conditions can differ in a single stage as in the thesis' study (section 7)
// (docs/EXPERIMENT_FILES.md). The glare between adaptation and acuity is the [glare] table's.
#include <string>

#include <toml++/toml.h>

#include "core/perception_settings.h"

namespace glarelab {

class TableReader;
struct ConditionRow;

// The settings of an experiment without a [perception] table: every stage off, the parameters
// at the stages' defaults.
PerceptionSettings perception_defaults();
// Reads [perception] if present (strictly: unknown keys and values out of range are ConfigErrors
// naming file:line:column and the key). Without the table, or for a switch it leaves out, every
// stage is off, so an experiment that does not mention perception shows its frames unchanged.
PerceptionSettings read_perception_section(TableReader& top);
// The table resolved_config_toml writes (every key explicit).
toml::table perception_section_toml(const PerceptionSettings& settings);
// The settings of one condition: its "perception" column, else the table's switches. The column
// is "none", "all" (adaptation, acuity, tone mapping and scotopic colour) or the enabled stages
// joined by '+', e.g. "acuity+scotopic"; the parameters are always the table's. ConfigError (at
// the row) for an unknown or repeated stage name.
PerceptionSettings perception_for(const PerceptionSettings& settings, const ConditionRow& row);
// Whether any stage is on (the glare, set by [glare], is not counted).
bool any_perception_stage(const PerceptionSettings& settings);
// "adaptation+tone_mapping", or "none": the stages that run, in Fig. 6.1's order.
std::string perception_stages_label(const PerceptionSettings& settings);

}  // namespace glarelab
