#include "core/errors.h"

#include <utility>

namespace glarelab {

std::string SourceLocation::to_string() const {
  // Compiler-style "file:line:column" so editors and terminals can jump to the spot; unknown
  // parts (0) are left out rather than printed as a misleading ":0".
  std::string text = file;
  if (line > 0) {
    text += ':' + std::to_string(line);
    if (column > 0) text += ':' + std::to_string(column);
  }
  return text;
}

namespace {

std::string compose(const SourceLocation& where, const std::string& key, const std::string& message) {
  std::string text = where.to_string();
  if (!text.empty()) text += ": ";
  if (!key.empty()) text += "key '" + key + "': ";
  return text + message;
}

}  // namespace

ConfigError::ConfigError(SourceLocation where, std::string key, const std::string& message)
    : std::runtime_error(compose(where, key, message)),
      where_(std::move(where)),
      key_(std::move(key)),
      message_(message) {}

}  // namespace glarelab
