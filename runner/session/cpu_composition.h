#pragma once
// The stimulus frame composed on the CPU, as FrameRenderer::compose and read_stimulus make it in GL,
// for a thread that holds no GL context: the worker preparing the next trial beside the current one
// (runner/session/trial_ahead.cpp). Laying a trial out took the display's thread 14 to 560 ms on two
// loaded cores with llvmpipe (three compositions of a 1024 x 512 frame read back, and the redraw
// of the frame on screen they forced): a dropped frame per trial (docs/PERFORMANCE.md, "Onsets of
// the demo on the real clock").
//
// It is the GL composition bit for bit where that is a copy: every placement shows its scene at the
// scene's own size, so stimuli/shaders/placed_image.frag fetches texel (x - rect.x, y - rect.y) for
// pixel (x, y) of the rectangle within its clip, and writes texel.rgb times the float scale with
// alpha 1 over a frame cleared to the float background (alpha 1). A scaled placement samples where
// the rasteriser's interpolation says, which only GL reproduces: exact() is false and the caller
// composes in GL.
#include <map>
#include <vector>

#include "core/image.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {

class CpuComposition {
 public:
  CpuComposition(int width_px, int height_px) : width_px_(width_px), height_px_(height_px) {}

  // The scene image a texture was uploaded from (FrameRenderer::upload): the same floats. The
  // image must outlive this object.
  void add_scene(const SceneTexture& texture, const ImageRGBA& image) { images_[&texture] = &image; }

  // Whether compose() gives GL's frame bit for bit: every placement's scene is known here and
  // shown at its own size.
  bool exact(const std::vector<Placement>& placements) const;

  // The frame cleared to `background_cd_m2` with `placements` drawn in order, row 0 at the top:
  // read_stimulus() after FrameRenderer::compose. Only where exact(placements).
  ImageRGBA compose(const std::vector<Placement>& placements, double background_cd_m2) const;

 private:
  int width_px_;
  int height_px_;
  std::map<const SceneTexture*, const ImageRGBA*> images_;
};

}  // namespace glarelab
