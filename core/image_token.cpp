#include "core/image_token.h"

#include <atomic>

namespace glarelab {

std::uint64_t new_image_token() {
  static std::atomic<std::uint64_t> last{0};
  return ++last;
}

}  // namespace glarelab
