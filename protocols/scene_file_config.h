#pragma once
// The keys of a [scenes] entry read from a file (docs/EXPERIMENT_FILES.md, "[scenes]"): what
// loading does with negative pixels, and what a scene that does not fit its place becomes.
#include <toml++/toml.h>

#include "core/scene_spec.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Reads `negative_pixels` ("refuse" | "clamp") and `fit` ("refuse" | "scale" | "crop") into
// `scene`; any other value is a ConfigError at the value naming the choices.
void read_scene_file_options(TableReader& reader, SceneSpec& scene);

// The inline table resolved_config_toml writes for a file scene (every key explicit).
toml::table scene_file_toml(const SceneSpec& scene);

}  // namespace glarelab
