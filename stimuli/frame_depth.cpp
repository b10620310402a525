// A composed frame's depth map and its warp through spectacles (stimuli/frame_depth.h).
#include "stimuli/frame_depth.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace glarelab {

std::vector<float> composed_depth_m(int width_px, int height_px, float background_depth_m,
                                    const std::vector<PlacedDepth>& placed) {
  std::vector<float> depth(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px), background_depth_m);
  for (const PlacedDepth& p : placed) {
    if (p.scene == nullptr) continue;
    const int x0 = std::max({0, p.rect.x_px, p.clip.x_px});
    const int y0 = std::max({0, p.rect.y_px, p.clip.y_px});
    const int x1 = std::min({width_px, p.rect.x_px + p.rect.width_px, p.clip.x_px + p.clip.width_px});
    const int y1 = std::min({height_px, p.rect.y_px + p.rect.height_px, p.clip.y_px + p.clip.height_px});
    const bool has_depth = !p.scene->depth.empty();
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const std::size_t source = static_cast<std::size_t>(y - p.rect.y_px) * static_cast<std::size_t>(p.scene->width_px) +
                                   static_cast<std::size_t>(x - p.rect.x_px);
        depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)] =
            has_depth ? p.scene->depth[source] : background_depth_m;
      }
  }
  return depth;
}

std::vector<float> depth_through_spectacles(const std::vector<float>& depth_m, const SpectacleLens& lens,
                                            const SpectacleFrame& frame, std::optional<double> scene_distance_mm,
                                            float outside_depth_m, int threads) {
  const SourceMap map = grid_source_map(lens, frame, kFraunhoferD_nm, SpectacleWarpOptions{}.grid_vertices,
                                        scene_distance_mm, threads);
  std::vector<float> seen(depth_m.size(), outside_depth_m);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      const glm::dvec2 at = map.at(x, y);
      const long sx = std::lround(at.x), sy = std::lround(at.y);
      if (sx < 0 || sy < 0 || sx >= frame.width_px || sy >= frame.height_px) continue;
      seen[static_cast<std::size_t>(y) * static_cast<std::size_t>(frame.width_px) + static_cast<std::size_t>(x)] =
          depth_m[static_cast<std::size_t>(sy) * static_cast<std::size_t>(frame.width_px) + static_cast<std::size_t>(sx)];
    }
  return seen;
}

}  // namespace glarelab
