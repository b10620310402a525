#pragma once
// The [procedure] keys of adaptive procedures (type = "staircase", "quest", "quest_plus" or "psi")
// and their interleaved tracks ([[procedure.staircases]]). See docs/EXPERIMENT_FILES.md.
#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Reads the adaptive keys of [procedure] (the defaults of every track) and the optional
// [[procedure.staircases]] array into experiment.adaptive. Parameters a staircase or QUEST
// cannot use (e.g. fewer reversals than step sizes) are ConfigErrors at the offending key.
void read_adaptive_procedure(TableReader& procedure, Experiment& experiment);

// With tracks_per_condition: replaces each track by one per condition row, in table order, named
// after the row ("ROW", or "ROW/TRACK" with several [[procedure.staircases]] entries), and clears
// the flag (the stored configuration lists the expanded tracks). Called once conditions are read.
void expand_tracks_per_condition(Experiment& experiment);

// Checks that every track names an existing condition row (called once conditions are read).
void check_adaptive_conditions(const Experiment& experiment);

}  // namespace glarelab
