#include "runner/session/keyboard_responses.h"

namespace glarelab {

std::optional<std::string> response_for_key(const std::string& key, const std::vector<std::string>& allowed_responses) {
  for (std::size_t i = 0; i < allowed_responses.size(); ++i) {
    if (key == allowed_responses[i]) return allowed_responses[i];
    if (i < 9 && key == std::to_string(i + 1)) return allowed_responses[i];
  }
  return std::nullopt;
}

std::string describe_response_keys(const std::vector<std::string>& allowed_responses) {
  std::string text;
  for (std::size_t i = 0; i < allowed_responses.size(); ++i) {
    if (!text.empty()) text += ", ";
    const std::string& name = allowed_responses[i];
    const bool is_key = name == "left" || name == "right" || name == "up" || name == "down" || name.size() == 1;
    text += (is_key ? "key '" + name + "' or " : std::string()) + "'" + std::to_string(i + 1) + "' for " + name;
  }
  return text + "; Escape ends the session";
}

}  // namespace glarelab
