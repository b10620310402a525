#pragma once
// Whether an experiment file states a key or leaves it to its default, asked after the experiment
// was read (a headset's display model takes the views' pitch only where the file states none:
// runner/session/headset_views.h).
#include <optional>
#include <string>
#include <string_view>

#include "core/errors.h"

namespace glarelab {

struct StatedKey {
  std::optional<SourceLocation> value;  // the key's value, when the file states it
  SourceLocation table;                 // its table ([display]), or the file, for a refusal of a left-out key
};

// `[table] key` of the experiment read from `source_file` (Experiment::source_file), read again
// from that file. A stored configuration (a resumed session's, "<session N config>") writes every
// key out, so it states every key. A file that can no longer be read states none.
StatedKey stated_key(const std::string& source_file, std::string_view table, std::string_view key);

}  // namespace glarelab
