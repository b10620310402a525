#include "core/user_cache_folder.h"

#include <cstdlib>

namespace glarelab {

std::optional<std::filesystem::path> user_cache_folder() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && cache[0] == '/')
    return std::filesystem::path(cache) / "glarelab";
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] == '/')
    return std::filesystem::path(home) / ".cache" / "glarelab";
  return std::nullopt;
}

}  // namespace glarelab
