#include "stimuli/scene_depth.h"

#include <cmath>
#include <cstddef>
#include <sstream>

#include "core/exr_io.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace glarelab {
namespace {

// Why a depth is refused, or nullptr when it is a place a surface can be.
const char* depth_problem(float depth_m) {
  if (std::isnan(depth_m)) return "NaN";
  if (depth_m == -INFINITY) return "-inf";
  if (depth_m == 0.0f) return "zero";
  if (depth_m < 0.0f) return "negative";
  return nullptr;  // positive finite, or +inf: a surface at infinity
}

}  // namespace

bool all_depths_positive(const std::vector<float>& depth_m) {
  std::size_t k = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  // An ordered comparison: false for a NaN, as the scalar test below.
  const __m128 zero = _mm_setzero_ps();
  __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (; k + 4 <= depth_m.size(); k += 4) ok = _mm_and_ps(ok, _mm_cmpgt_ps(_mm_loadu_ps(&depth_m[k]), zero));
  if (_mm_movemask_ps(ok) != 0xF) return false;
#endif
  for (; k < depth_m.size(); ++k)
    if (!(depth_m[k] > 0.0f)) return false;
  return true;
}

void check_scene_depth(const std::vector<float>& depth_m, int width_px, int height_px, const std::string& file) {
  const std::size_t expected = static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  if (width_px <= 0 || height_px <= 0 || depth_m.size() != expected) {
    throw ImageError("stimuli/scene_depth: " + file + ": the depth map has " + std::to_string(depth_m.size()) +
                     " values for a " + std::to_string(width_px) + " x " + std::to_string(height_px) +
                     " px image; one a pixel expected");
  }
  if (all_depths_positive(depth_m)) return;  // the common case, in one vector pass
  for (std::size_t k = 0; k < depth_m.size(); ++k) {
    const char* problem = depth_problem(depth_m[k]);
    if (problem == nullptr) continue;
    std::ostringstream message;
    message << "stimuli/scene_depth: " << file << ": Z at pixel (" << k % static_cast<std::size_t>(width_px) << ", "
            << k / static_cast<std::size_t>(width_px) << ") is " << problem << " (" << depth_m[k]
            << "); depths are positive metres from the eye, +inf for a surface at infinity";
    throw ImageError(message.str());
  }
}

std::vector<float> scene_depth_m(const ImageRGBA& image, const std::string& file, const DisplaySpec& display) {
  if (image.depth.empty()) {
    if (!(display.viewing_distance_mm > 0.0) || !std::isfinite(display.viewing_distance_mm))
      throw ImageError("stimuli/scene_depth: " + file + ": the display's viewing distance " +
                       std::to_string(display.viewing_distance_mm) + " mm is not a positive distance");
    return std::vector<float>(static_cast<std::size_t>(image.width_px) * static_cast<std::size_t>(image.height_px),
                              static_cast<float>(display.viewing_distance_mm / 1000.0));
  }
  check_scene_depth(image.depth, image.width_px, image.height_px, file);
  return image.depth;
}

}  // namespace glarelab
