#pragma once
// The overlays a session draws over its frames ([presentation]): the trial's question above the
// stimuli, screen and feedback texts centred, the fixation cross. Sizes come from degrees of visual
// angle through the display geometry (stimuli/display_model.h); each distinct text is rasterised
// and uploaded once.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "protocols/experiment.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {

class PresentationOverlays {
 public:
  PresentationOverlays(FrameRenderer& renderer, const Experiment& experiment);

  // The question centred above the stimulus rectangles, half a line above the highest; empty when
  // question_above_stimuli is false or the question is empty.
  std::vector<Placement> question(const std::string& text, const std::vector<PixelRect>& stimuli);
  // A screen's or the feedback's text, centred on the screen.
  std::vector<Placement> centred_text(const std::string& text);
  std::vector<Placement> fixation();

  int line_height_px() const { return line_height_px_; }
  int fixation_size_px() const { return fixation_size_px_; }

 private:
  const SceneTexture* text_texture(const std::string& text);  // null for text without glyphs
  Placement placed(const SceneTexture& texture, PixelRect rect) const;

  FrameRenderer& renderer_;
  PresentationSpec spec_;
  int line_height_px_ = 1;
  int max_width_px_ = 1;
  int fixation_size_px_ = 3;
  std::map<std::string, SceneTexture> texts_;
  std::optional<SceneTexture> cross_;
};

}  // namespace glarelab
