#pragma once
// The pairwise design of Ritschel et al. 2009, section 6.1, generated from a few keys of
// [procedure] (forced choice, `design = "all_pairs"`): "two images of the same scene where each
// of the displays was either enhanced by application of dynamic or static glare or not. All
// possible combinations were presented for each scene ... according to one of three
// instructions ... separately and in randomized order. The currently required task was indicated
// above the display in each trial."
//
// For every instruction, every scene of `mode_scenes` and every unordered pair of `glare_modes`
// (in list order, a before b) one condition row; with counterbalance_sides each row runs both ways
// round, so every mode is shown equally often on the left and on the right. Each instruction is a
// block (its question is the trials' question), ordered by [procedure] block_order.
#include <optional>
#include <vector>

#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

struct GeneratedDesign {
  std::vector<ConditionRow> rows;   // columns: name, scene, instruction, condition_a, condition_b,
                                    // scene_a, scene_b, question, scored
  std::vector<BlockSpec> blocks;    // one per instruction, in the order listed
  SourceLocation where;             // the `design` key: where generated rows are reported
};

// Reads design, glare_modes, instructions and mode_scenes of [procedure] (forced choice only;
// for other procedures the keys stay unknown). Nothing unless design = "all_pairs"; "rows" (the
// default) means the condition table is written out in [conditions].
std::optional<GeneratedDesign> read_pair_design(TableReader& procedure, const Experiment& experiment);

}  // namespace glarelab
