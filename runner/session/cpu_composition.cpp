#include "runner/session/cpu_composition.h"

#include <stdexcept>

#include "core/pixel_rect.h"

namespace glarelab {

bool CpuComposition::exact(const std::vector<Placement>& placements) const {
  for (const Placement& placement : placements) {
    const auto found = images_.find(placement.scene);
    if (found == images_.end()) return false;
    if (placement.rect.width_px != found->second->width_px || placement.rect.height_px != found->second->height_px)
      return false;
  }
  return true;
}

ImageRGBA CpuComposition::compose(const std::vector<Placement>& placements, double background_cd_m2) const {
  if (!exact(placements))
    throw std::logic_error("cpu composition: a placement scaled or of an unknown scene (GL composes it)");
  // glClearNamedFramebufferfv with the background as a float, alpha 1 (FrameRenderer::compose).
  const auto background = static_cast<float>(background_cd_m2);
  ImageRGBA frame(width_px_, height_px_, background);
  for (std::size_t i = 3; i < frame.rgba.size(); i += 4) frame.rgba[i] = 1.0f;
  const PixelRect whole{0, 0, width_px_, height_px_};
  for (const Placement& placement : placements) {
    const ImageRGBA& scene = *images_.at(placement.scene);
    // The scissor (the clip) and the rectangle's pixels, within the framebuffer.
    const PixelRect drawn = intersection(intersection(placement.rect, placement.clip), whole);
    if (drawn.empty()) continue;
    // uScale is a float uniform; the shader's product is one IEEE single multiply per channel.
    const auto scale = static_cast<float>(placement.scale_cd_m2);
    for (int y = drawn.y_px; y < drawn.bottom_px(); ++y) {
      const float* texel = scene.pixel(drawn.x_px - placement.rect.x_px, y - placement.rect.y_px);
      float* out = frame.pixel(drawn.x_px, y);
      for (int x = 0; x < drawn.width_px; ++x, texel += 4, out += 4) {
        out[0] = texel[0] * scale;
        out[1] = texel[1] * scale;
        out[2] = texel[2] * scale;
        out[3] = 1.0f;
      }
    }
  }
  return frame;
}

}  // namespace glarelab
