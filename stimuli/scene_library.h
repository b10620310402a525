#pragma once
// The scenes an experiment shows, read from OpenEXR (or drawn by their generator,
// stimuli/spencer_scenes.h) once and kept in cd/m2.
#include <map>
#include <string>

#include "core/display_spec.h"
#include "core/image.h"
#include "core/scene_spec.h"

namespace glarelab {

// GL_MAX_TEXTURE_SIZE is at least 16384 in every OpenGL 4.5 implementation: larger scenes could
// not be uploaded on some displays, and would fail mid-session.
inline constexpr int kMaxSceneTexturePx = 16384;
// The brightest scene taken, in cd/m2 after its scale_cd_m2: the sun's disc is about 1.6e9.
// Glare sums a frame's luminances in float (FFT convolutions over up to 2^26 pixels); a 3e38 cd/m2
// scene overflowed them to inf and gave NaN frames without a word. 1e12 x 2^26 stays far inside
// float's range.
inline constexpr double kMaxSceneLuminance_cd_m2 = 1e12;

struct LoadedScene {
  SceneSpec spec;
  ImageRGBA image_cd_m2;  // pixel values times scale_cd_m2: linear Rec.709, Y in cd/m2
  double peak_cd_m2 = 0.0;
  double mean_cd_m2 = 0.0;
};

class SceneLibrary {
 public:
  // Reads every scene (an experiment's scenes, by name). Throws ImageError naming the file for missing or corrupt
  // files, and for NaN, Inf or negative pixels (with their counts): a luminance cannot be any of
  // those, and a glare model fed one would spread it over the whole frame. A Z channel is checked
  // as stimuli/scene_depth.h says (ImageError naming the file, the channel and the first bad pixel). Generated scenes are
  // drawn for `display` (their sizes are degrees, their luminances fractions of its peak).
  SceneLibrary(const std::map<std::string, SceneSpec>& scenes, const DisplaySpec& display);

  const LoadedScene& get(const std::string& name) const;
  const std::map<std::string, LoadedScene>& scenes() const { return scenes_; }
  std::map<std::string, double> peak_luminances_cd_m2() const;

 private:
  std::map<std::string, LoadedScene> scenes_;
};

}  // namespace glarelab
