#pragma once
// The QUEST+ and Psi keys of [procedure] (type = "quest_plus" or "psi", protocols/quest_plus.h):
// grids, psychometric function, stimulus columns, and the interleaved tracks of
// [[procedure.staircases]], whose keys overlay those of [procedure]. See docs/EXPERIMENT_FILES.md.
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Appends the tracks to experiment.adaptive.tracks: one named after the procedure, or one per
// [[procedure.staircases]] entry. A key that makes the track invalid is a ConfigError at that key
// (in the entry when it sets the key, else in [procedure]).
void read_quest_plus_tracks(TableReader& procedure, Experiment& experiment);

}  // namespace glarelab
