#include "analysis/session_observer_eye.h"

#include <sstream>

#include <toml++/toml.h>

#include "core/text_limits.h"

namespace glarelab::analysis {

std::optional<StoredObserverEye> stored_observer_eye(const std::string& config_toml) {
  toml::table root;
  if (toml_limit_fault(config_toml)) return std::nullopt;  // toml++ would recurse past the stack
  try {
    root = toml::parse(config_toml);
  } catch (const toml::parse_error&) {
    return std::nullopt;
  }
  const std::optional<double> age = root["observer"]["age_years"].value<double>();
  const std::optional<double> pigmentation = root["observer"]["pigmentation"].value<double>();
  if (!age || !pigmentation) return std::nullopt;
  return StoredObserverEye{*age, *pigmentation};
}

std::string observer_eye_text(const std::string& config_toml) {
  const std::optional<StoredObserverEye> eye = stored_observer_eye(config_toml);
  if (!eye) return "not stored";
  std::ostringstream out;
  out << eye->age_years << " years, pigmentation " << eye->pigmentation;
  return out.str();
}

}  // namespace glarelab::analysis
