#pragma once
// What the analysis reads of the procedure a session stored (sessions.config, the resolved
// experiment as TOML): the number of answer alternatives, which fixes a fit's guess rate.
#include <optional>
#include <string>

namespace glarelab::analysis {

// `[procedure] alternatives` of a stored configuration (2, or 3 with "neither"), or nothing when
// the text is not TOML or has no such key.
std::optional<int> stored_alternatives(const std::string& config_toml);

}  // namespace glarelab::analysis
