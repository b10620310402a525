#pragma once
// Which key gives which response: a key whose name equals an allowed response ("left", "right",
// "y"), or the digit of its position in the list ("1" for the first). Escape aborts.
#include <optional>
#include <string>
#include <vector>

namespace glarelab {
std::optional<std::string> response_for_key(const std::string& key, const std::vector<std::string>& allowed_responses);
std::string describe_response_keys(const std::vector<std::string>& allowed_responses);
}  // namespace glarelab
