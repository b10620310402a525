#include "analysis/stored_procedure.h"

#include <toml++/toml.h>

namespace glarelab::analysis {

std::optional<int> stored_alternatives(const std::string& config_toml) {
  toml::table root;
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
