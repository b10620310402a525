#include "analysis/stored_procedure.h"

#include <toml++/toml.h>

#include "core/text_limits.h"

namespace glarelab::analysis {

std::optional<int> stored_alternatives(const std::string& config_toml) {
  toml::table root;
  if (toml_limit_fault(config_toml)) return std::nullopt;  // toml++ would recurse past the stack
  try {
    root = toml::parse(config_toml);
  } catch (const toml::parse_error&) {
    return std::nullopt;
  }
  const std::optional<std::int64_t> alternatives = root["procedure"]["alternatives"].value<std::int64_t>();
  if (!alternatives || *alternatives < 2) return std::nullopt;
  return static_cast<int>(*alternatives);
}

}  // namespace glarelab::analysis
