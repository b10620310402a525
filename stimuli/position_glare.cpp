#include "stimuli/position_glare.h"

#include <stdexcept>

namespace glarelab {

ImageRGBA apply_layered_glare(GlareStage& stage, const ImageRGBA& composed_cd_m2, const std::vector<GlareLayer>& layers,
                              double time_s, const std::optional<GazePoint>& gaze,
                              std::vector<GlareFrameReport>* reports, std::optional<double> field_luminance) {
  const double field_luminance_cd_m2 = field_luminance ? *field_luminance : mean_luminance(composed_cd_m2);
  // Background part: what no layer holds (exactly zero inside a placement, which replaces the
  // background there; the background luminance elsewhere).
  ImageRGBA result = composed_cd_m2;
  for (const GlareLayer& layer : layers) {
    if (layer.image_cd_m2.width_px != composed_cd_m2.width_px || layer.image_cd_m2.height_px != composed_cd_m2.height_px)
      throw std::invalid_argument("glare layers: a layer of " + std::to_string(layer.image_cd_m2.width_px) + "x" +
                                  std::to_string(layer.image_cd_m2.height_px) + " px for a frame of " +
                                  std::to_string(composed_cd_m2.width_px) + "x" +
                                  std::to_string(composed_cd_m2.height_px) + " px");
    for (std::size_t i = 0; i < result.rgba.size(); ++i)
      if (i % 4 != 3) result.rgba[i] -= layer.image_cd_m2.rgba[i];
  }
  for (const GlareLayer& layer : layers) {
    GlareFrameReport report;
    ImageRGBA glared = layer.mode == GlareMode::control
                           ? layer.image_cd_m2
                           : stage.apply(layer.image_cd_m2, layer.mode, time_s, &report, gaze, field_luminance_cd_m2);
    if (layer.keep_peak && layer.mode != GlareMode::control) {
      const double before = max_luminance(layer.image_cd_m2), after = max_luminance(glared);
      if (before > 0.0 && after > 0.0) {
        const auto scale = static_cast<float>(before / after);
        for (std::size_t i = 0; i < glared.rgba.size(); ++i)
          if (i % 4 != 3) glared.rgba[i] *= scale;
      }
    }
    if (layer.mode != GlareMode::control && reports != nullptr) reports->push_back(report);
    for (std::size_t i = 0; i < result.rgba.size(); ++i)
      if (i % 4 != 3) result.rgba[i] += glared.rgba[i];
  }
  return result;
}

}  // namespace glarelab
