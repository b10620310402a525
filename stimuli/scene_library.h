#pragma once
// The scenes an experiment shows, read from OpenEXR (or drawn by their generator,
// stimuli/spencer_scenes.h) once and kept in cd/m2.
#include <map>
#include <string>
#include <vector>

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
  // negative_pixels = "clamp": the pixels that had a negative channel (each such channel set to 0)
  // and the fraction of the scene's energy that removed: sum over channels of w_c |min(v_c, 0)|
  // over sum of w_c |v_c|, w the Rec.709 luminance weights (0.2126, 0.7152, 0.0722), so a clamped
  // blue channel counts for as little as it would add to luminance.
  std::size_t clamped_pixels = 0;
  double clamped_energy_fraction = 0.0;
  // fit = "scale" or "crop" applied (stimuli/scene_fit.h): what the image became, else empty.
  std::string fit_note;
};

// "scene 'NAME': 845 negative pixels set to 0 (negative_pixels = "clamp"), 1.2e-05 of its energy",
// or empty when nothing was clamped. Printed by validate and render, and logged by the session.
std::string describe_clamping(const std::string& name, const LoadedScene& scene);

class SceneLibrary;
// Every scene's clamping and fitting (describe_clamping, LoadedScene::fit_note), one line each.
std::vector<std::string> scene_load_notes(const SceneLibrary& scenes);

// A frame glarelab writes as OpenEXR (render, run --save-frames) made loadable as a scene with no
// option: the glare's FFT round-off leaves channels a little below 0 (about -2e-5 cd/m2 beside a
// peak of hundreds), which scene loading would refuse. Channels negative by at most
// kRoundOffNegativeFraction of the frame's largest channel are set to 0; deeper ones are kept, so
// a real fault still shows when the file is loaded. Returns the channels set to 0.
inline constexpr double kRoundOffNegativeFraction = 1e-4;
std::size_t zero_round_off_negatives(ImageRGBA& frame);

class SceneLibrary {
 public:
  // Reads every scene (an experiment's scenes, by name). Throws ImageError naming the file for missing or corrupt
  // files, and for NaN, Inf or negative pixels (with their counts): a luminance cannot be any of
  // those, and a glare model fed one would spread it over the whole frame. A scene whose entry says
  // negative_pixels = "clamp" has its negative channels set to 0 instead (counted in LoadedScene). A Z channel is checked
  // as stimuli/scene_depth.h says (ImageError naming the file, the channel and the first bad pixel). Generated scenes are
  // drawn for `display` (their sizes are degrees, their luminances fractions of its peak).
  SceneLibrary(const std::map<std::string, SceneSpec>& scenes, const DisplaySpec& display);

  const LoadedScene& get(const std::string& name) const;
  const std::map<std::string, LoadedScene>& scenes() const { return scenes_; }
  std::map<std::string, double> peak_luminances_cd_m2() const;
  // A scene's image replaced by its fitted version (stimuli/scene_fit.h), its peak and mean
  // recomputed and `fit_note` kept for the notes. Throws std::out_of_range for an unknown name.
  void replace_image(const std::string& name, ImageRGBA image, std::string fit_note);

 private:
  std::map<std::string, LoadedScene> scenes_;
};

}  // namespace glarelab
