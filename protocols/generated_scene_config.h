#pragma once
// Scenes drawn at load time ([scenes] entries with a `generator`, docs/EXPERIMENT_FILES.md,
// "Generated scenes"): the stimuli of Spencer et al. 1995, section 4 (stimuli/spencer_scenes.h).
#include <toml++/toml.h>

#include "core/display_spec.h"
#include "core/scene_spec.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Reads one generated scene's keys (the table has a `generator`). Unknown keys, keys of another
// generator and values out of range, or sizes that do not fit the image on `display`, are
// ConfigErrors at the key.
GeneratedSceneSpec read_generated_scene(TableReader& reader, const DisplaySpec& display);

// The inline table resolved_config_toml writes (every key explicit).
toml::table generated_scene_toml(const GeneratedSceneSpec& spec);

}  // namespace glarelab
