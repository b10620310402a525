#pragma once
// What each scene file of a session held when the session started, checked when it is resumed.
// The stored configuration keeps a scene's path, not its pixels: a file replaced between a run
// and its resume would change the stimulus of the trials still to come without a word.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/scene_spec.h"
#include "runner/store/result_store.h"

namespace glarelab {

// One line per scene read from a file: "NAME<tab>fnv1a64=HEX bytes=N<tab>PATH" (generated scenes
// have no file and no line). The session's `scene_fingerprint` event holds them (docs/DATABASE.md).
std::string scene_fingerprints(const std::map<std::string, SceneSpec>& scenes);

// The fingerprints stored with session `session_id` (its `scene_fingerprint` events).
std::vector<std::string> stored_scene_fingerprints(const ResultStore& store, std::int64_t session_id);

// Throws ConfigError when a file of `scenes` (the stored design's) no longer has the fingerprint
// stored for session `session_id` (changed, or gone), at the scene's key in the experiment file
// (`scenes_in_file`) where it has one. Sessions stored before fingerprints were kept have none:
// nothing to check.
void check_scene_fingerprints(const std::string& stored, const std::map<std::string, SceneSpec>& scenes,
                              const std::map<std::string, SceneSpec>& scenes_in_file, std::int64_t session_id);

}  // namespace glarelab
