#include "runner/session/presentation_overlays.h"

#include <algorithm>
#include <cmath>

#include "stimuli/display_model.h"
#include "stimuli/overlay_image.h"

namespace glarelab {

PresentationOverlays::PresentationOverlays(FrameRenderer& renderer, const Experiment& experiment)
    : renderer_(renderer), spec_(experiment.presentation) {
  const DisplayModel display(experiment.display);
  line_height_px_ = std::max(1, static_cast<int>(std::lround(display.pixels_for_centred_span(spec_.text_height_deg))));
  fixation_size_px_ = std::max(3, static_cast<int>(std::lround(display.pixels_for_centred_span(spec_.fixation_size_deg))));
  // Lines wrap within 90 % of the screen's width, so long instructions keep a margin.
  max_width_px_ = std::max(1, renderer.width_px() * 9 / 10);
}

const SceneTexture* PresentationOverlays::text_texture(const std::string& text) {
  auto found = texts_.find(text);
  if (found == texts_.end()) {
    const ImageRGBA image = text_overlay(text, line_height_px_, max_width_px_, spec_.text_cd_m2);
    // Text without a visible glyph (blanks only) rasterises to an empty image: nothing to draw.
    if (image.width_px == 0 || image.height_px == 0) return nullptr;
    found = texts_.emplace(text, renderer_.upload(image)).first;
  }
  return &found->second;
}

Placement PresentationOverlays::placed(const SceneTexture& texture, PixelRect rect) const {
  return Placement{&texture, 1.0, rect, rect};
}

std::vector<Placement> PresentationOverlays::question(const std::string& text, const std::vector<PixelRect>& stimuli) {
  if (!spec_.question_above_stimuli || text.empty()) return {};
  const SceneTexture* texture = text_texture(text);
  if (texture == nullptr) return {};
  return {placed(*texture, rect_above(stimuli, texture->width_px, texture->height_px, renderer_.width_px(),
                                      renderer_.height_px(), line_height_px_ / 2))};
}

std::vector<Placement> PresentationOverlays::centred_text(const std::string& text) {
  const SceneTexture* texture = text.empty() ? nullptr : text_texture(text);
  if (texture == nullptr) return {};
  return {placed(*texture, centred_rect(texture->width_px, texture->height_px, renderer_.width_px(), renderer_.height_px()))};
}

std::vector<Placement> PresentationOverlays::fixation() {
  if (!cross_) cross_ = renderer_.upload(fixation_cross(fixation_size_px_, spec_.text_cd_m2));
  return {placed(*cross_, centred_rect(cross_->width_px, cross_->height_px, renderer_.width_px(), renderer_.height_px()))};
}

}  // namespace glarelab
