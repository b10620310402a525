#pragma once
// Reading and writing the block keys of an experiment file: [[blocks]] and, in [procedure],
// block_order and participant_number (docs/EXPERIMENT_FILES.md, "Blocks").
#include <toml++/toml.h>

#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// block_order and participant_number of [procedure].
void read_block_keys(TableReader& procedure, Experiment& experiment);
// The [[blocks]] array of the document root, if present.
void read_blocks_section(TableReader& top, Experiment& experiment);
// After the condition rows are known: block names distinct, the conditions they name exist, the
// procedure takes blocks, the order keys are only given with blocks. Throws ConfigError.
void check_blocks(const Experiment& experiment);

// What resolved_config_toml writes: the keys added to [procedure] (only with blocks, so
// experiments without blocks keep their stored configuration) and the [[blocks]] array.
void insert_block_keys(const DesignSpec& design, toml::table& procedure);
toml::array blocks_toml(const DesignSpec& design);

}  // namespace glarelab
