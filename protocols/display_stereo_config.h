#pragma once
// The keys of [display] that say how the frame reaches the eyes: `stereo` (one frame for both, or
// each eye its half: docs/STEREO.md) and `output` (where a study is shown when `glarelab run` is
// given no --display: a window, or a head-mounted display through OpenXR).
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// [display] stereo = "none" | "side_by_side" into experiment.display.stereo (width_px read before).
void read_display_stereo(TableReader& reader, Experiment& experiment);
// [display] output = "window" | "openxr" into experiment.display_output and its location.
void read_display_output(TableReader& reader, Experiment& experiment);

}  // namespace glarelab
