#include "stimuli/scene_library.h"

#include <stdexcept>

#include "core/exr_io.h"
#include "core/number_text.h"
#include "stimuli/scene_depth.h"
#include "stimuli/spencer_scenes.h"

namespace glarelab {

SceneLibrary::SceneLibrary(const std::map<std::string, SceneSpec>& scenes, const DisplaySpec& display) {
  for (const auto& [name, spec] : scenes) {
    ExrReadResult read;
    if (spec.generated) {
      try {
        read.image = draw_generated_scene(*spec.generated, display);
      } catch (const std::invalid_argument& error) {
        throw ImageError("scene '" + name + "': " + error.what());
      }
    } else {
      read = read_exr(spec.file);
    }
    if (read.image.width_px > kMaxSceneTexturePx || read.image.height_px > kMaxSceneTexturePx)
      throw ImageError(spec.file + ": scene '" + name + "' is " + std::to_string(read.image.width_px) + " x " +
                       std::to_string(read.image.height_px) + " px; at most " + std::to_string(kMaxSceneTexturePx) +
                       " px a side (the texture size every OpenGL 4.5 driver must take)");
    const NonFiniteReport report = inspect_pixels(read.image);
    if (!report.clean()) {
      throw ImageError(spec.file + ": scene '" + name + "' has " + report.describe() +
                       "; luminances must be finite and non-negative");
    }
    // The Z channel (metres from the eye), checked now so that a bad depth stops the run before
    // anything is written: NaN, -inf, zero and negative depths are no place a surface can be.
    if (!read.image.depth.empty())
      check_scene_depth(read.image.depth, read.image.width_px, read.image.height_px,
                        (spec.file.empty() ? "scene '" + name + "'" : spec.file + ": scene '" + name + "'"));
    LoadedScene scene;
    scene.spec = spec;
    scene.image_cd_m2 = std::move(read.image);
    const auto scale = static_cast<float>(spec.scale_cd_m2);
    for (std::size_t i = 0; i < scene.image_cd_m2.rgba.size(); i += 4) {
      scene.image_cd_m2.rgba[i] *= scale;
      scene.image_cd_m2.rgba[i + 1] *= scale;
      scene.image_cd_m2.rgba[i + 2] *= scale;
    }
    scene.peak_cd_m2 = max_luminance(scene.image_cd_m2);
    if (!(scene.peak_cd_m2 <= kMaxSceneLuminance_cd_m2))  // inf too: a large pixel times a large scale
      throw ImageError((spec.file.empty() ? "" : spec.file + ": ") + "scene '" + name + "' peaks at " +
                       number_text(scene.peak_cd_m2) + " cd/m2 (pixel values times scale_cd_m2); glarelab takes "
                       "scenes up to 1e12 cd/m2 (the sun's disc is about 1.6e9)");
    scene.mean_cd_m2 = mean_luminance(scene.image_cd_m2);
    scenes_.emplace(name, std::move(scene));
  }
}

const LoadedScene& SceneLibrary::get(const std::string& name) const {
  const auto found = scenes_.find(name);
  if (found == scenes_.end()) throw std::out_of_range("no scene named '" + name + "'");
  return found->second;
}

std::map<std::string, double> SceneLibrary::peak_luminances_cd_m2() const {
  std::map<std::string, double> peaks;
  for (const auto& [name, scene] : scenes_) peaks[name] = scene.peak_cd_m2;
  return peaks;
}

}  // namespace glarelab
