#pragma once
// `--eye-from FILE` of `glarelab psf` and `glarelab eye-trace` (runner/cli): the eye model's parameters from an
// experiment file's [glare.eye] table (protocols/eye_parameters_config.h, docs/EXPERIMENT_FILES.md),
// so that the eye these commands show is the eye a session with that file uses. Only that table is
// read; the rest of the file is not checked (it need not name scenes that exist here).
#include <string>

#include "glare/eye/eye_parameters.h"

namespace glarelab {

// Reads FILE's [glare.eye] over `parameters`: ConfigError at file:line:column naming the key for a
// TOML syntax error, a value of the wrong type or out of its bounds, a broken cross-field rule or an
// unknown key; at the file for a file that cannot be read or has no [glare.eye] table.
void read_glare_eye_file(const std::string& path, EyeParameters& parameters);

}  // namespace glarelab
