#include "stimuli/scene_library.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/exr_io.h"
#include "core/number_text.h"
#include "stimuli/scene_depth.h"
#include "stimuli/spencer_scenes.h"

namespace glarelab {
namespace {

// Sets negative colour channels to 0 and returns the pixels that had one and the fraction of the
// luminance-weighted energy removed (LoadedScene). NaN and Inf are refused before this.
std::pair<std::size_t, double> clamp_negative_channels(ImageRGBA& image) {
  constexpr double kWeights[3] = {0.2126, 0.7152, 0.0722};  // Rec.709 Y (ITU-R BT.709-6, item 3.2)
  std::size_t pixels = 0;
  double clamped = 0.0, total = 0.0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    bool negative = false;
    for (int c = 0; c < 3; ++c) {
      float& value = image.rgba[i + static_cast<std::size_t>(c)];
      total += kWeights[c] * std::fabs(static_cast<double>(value));
      if (value < 0.0f) {
        clamped -= kWeights[c] * static_cast<double>(value);
        value = 0.0f;
        negative = true;
      }
    }
    pixels += negative ? 1 : 0;
  }
  return {pixels, total > 0.0 ? clamped / total : 0.0};
}

}  // namespace

std::string describe_clamping(const std::string& name, const LoadedScene& scene) {
  if (scene.clamped_pixels == 0) return {};
  std::ostringstream text;
  text << "scene '" << name << "': " << scene.clamped_pixels << " negative pixel"
       << (scene.clamped_pixels == 1 ? "" : "s") << " set to 0 (negative_pixels = \"clamp\"), "
       << scene.clamped_energy_fraction << " of its energy";
  return text.str();
}

std::size_t zero_round_off_negatives(ImageRGBA& frame) {
  float peak = 0.0f;
  for (std::size_t i = 0; i < frame.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (std::isfinite(frame.rgba[i + c])) peak = std::max(peak, frame.rgba[i + c]);
  // Float32 FFTs of N points err by about eps log2 N of the largest value (eps 6e-8, N up to 2^24
  // for a 4096 px square): 1.4e-6; the bound leaves a factor of 70 above that.
  const float floor = -static_cast<float>(kRoundOffNegativeFraction) * peak;
  std::size_t zeroed = 0;
  for (std::size_t i = 0; i < frame.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (frame.rgba[i + c] < 0.0f && frame.rgba[i + c] >= floor) {
        frame.rgba[i + c] = 0.0f;
        ++zeroed;
      }
  return zeroed;
}

std::vector<std::string> scene_load_notes(const SceneLibrary& scenes) {
  std::vector<std::string> notes;
  for (const auto& [name, scene] : scenes.scenes()) {
    if (const std::string clamping = describe_clamping(name, scene); !clamping.empty()) notes.push_back(clamping);
    if (!scene.fit_note.empty()) notes.push_back(scene.fit_note);
  }
  return notes;
}

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
    const bool only_negative = report.nan_pixels == 0 && report.inf_pixels == 0;
    std::pair<std::size_t, double> clamped{0, 0.0};
    if (!report.clean() && only_negative && spec.negative_pixels == NegativePixels::clamp) {
      clamped = clamp_negative_channels(read.image);
    } else if (!report.clean()) {
      // Negatives alone have a way forward, named here; NaN and Inf have none (no value to clamp to).
      throw ImageError(spec.file + ": scene '" + name + "' has " + report.describe() +
                       "; luminances must be finite and non-negative" +
                       (only_negative ? " (negative_pixels = \"clamp\" in the scene's [scenes] entry sets them to 0)"
                                      : ""));
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
    scene.clamped_pixels = clamped.first;
    scene.clamped_energy_fraction = clamped.second;
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

void SceneLibrary::replace_image(const std::string& name, ImageRGBA image, std::string fit_note) {
  const auto found = scenes_.find(name);
  if (found == scenes_.end()) throw std::out_of_range("no scene named '" + name + "'");
  LoadedScene& scene = found->second;
  scene.image_cd_m2 = std::move(image);
  scene.peak_cd_m2 = max_luminance(scene.image_cd_m2);
  scene.mean_cd_m2 = mean_luminance(scene.image_cd_m2);
  scene.fit_note = std::move(fit_note);
}

std::map<std::string, double> SceneLibrary::peak_luminances_cd_m2() const {
  std::map<std::string, double> peaks;
  for (const auto& [name, scene] : scenes_) peaks[name] = scene.peak_cd_m2;
  return peaks;
}

}  // namespace glarelab
