#include "runner/session/scene_places.h"

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/errors.h"
#include "protocols/procedure.h"
#include "stimuli/scene_fit.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {
namespace {

std::string size_text(int width_px, int height_px) {
  return std::to_string(width_px) + " x " + std::to_string(height_px) + " px";
}

// The scenes a trial shows side by side: the first plan's (every plan of a procedure shows as
// many); a sequential forced choice shows them one at a time.
std::size_t scenes_side_by_side(const Experiment& experiment, const SceneLibrary& scenes) {
  const std::unique_ptr<Procedure> procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  const std::size_t shown = procedure->finished() ? 0 : procedure->next_trial().scenes.size();
  if (experiment.forced_choice.layout == "sequential" && shown > 0) return 1;
  return std::max<std::size_t>(shown, 1);
}

std::string describe_place(const Experiment& experiment, const PixelRect& place, std::size_t shown) {
  const DisplaySpec& display = experiment.display;
  std::ostringstream text;
  text << "its place is " << size_text(place.width_px, place.height_px);
  if (shown > 1)
    text << ", a column of " << shown << " scenes side by side, " << stimulus_gap_px(display) << " px ("
         << display.stimulus_gap_deg << " deg) apart,";
  text << " on the " << size_text(display.width_px, display.height_px)
       << (display.stereo == StereoMode::none ? " display" : " display's eye half");
  return text.str();
}

// The narrowest of `shown` columns side by side (a stereo display: in an eye's half).
PixelRect place_of(const Experiment& experiment, std::size_t shown) {
  const std::vector<EyeView> views = stereo_eye_views(experiment.display);
  const PixelRect view = views.empty() ? PixelRect{0, 0, experiment.display.width_px, experiment.display.height_px}
                                       : views.front().viewport;
  std::vector<PixelRect> columns;
  try {
    side_by_side_layout(view.width_px, view.height_px, std::vector<PixelRect>(shown, PixelRect{0, 0, 1, 1}), &columns,
                        stimulus_gap_px(experiment.display));
  } catch (const std::invalid_argument& error) {
    throw ConfigError(experiment.stimulus_gap_where, "display.stimulus_gap_deg", error.what());
  }
  PixelRect place = columns.front();
  for (const PixelRect& column : columns) place.width_px = std::min(place.width_px, column.width_px);
  return place;
}

}  // namespace

PixelRect scene_place(const Experiment& experiment, const SceneLibrary& scenes) {
  return place_of(experiment, scenes_side_by_side(experiment, scenes));
}

void fit_scenes_to_places(const Experiment& experiment, SceneLibrary& scenes, bool refuse_misfits) {
  const std::size_t shown = scenes_side_by_side(experiment, scenes);  // makes a procedure: once
  const PixelRect place = place_of(experiment, shown);
  std::vector<std::string> names;
  for (const auto& [name, scene] : scenes.scenes()) names.push_back(name);
  for (const std::string& name : names) {
    const LoadedScene& scene = scenes.get(name);
    const int width_px = scene.image_cd_m2.width_px, height_px = scene.image_cd_m2.height_px;
    if (width_px <= place.width_px && height_px <= place.height_px) continue;
    const std::string where = "scene '" + name + "' (" + size_text(width_px, height_px) + ") does not fit: " +
                              describe_place(experiment, place, shown);
    const std::string remedy = "add fit = \"scale\" (the whole scene, smaller) or fit = \"crop\" (its centre) to its "
                               "[scenes] entry, use a smaller image or a larger display";
    if (scene.spec.fit == SceneFit::refuse) {
      if (experiment.display.stereo != StereoMode::none) continue;  // check_stereo_layout says why
      if (refuse_misfits) throw ConfigError(scene.spec.where, "scenes." + name, where + ". To show it, " + remedy);
      // A run shows it as the layout places it, cut by its column; said, not silent.
      scenes.replace_image(name, ImageRGBA(scene.image_cd_m2),
                           where + ": shown cut by its column (glarelab validate refuses this; " + remedy + ")");
      continue;
    }
    ImageRGBA fitted;
    std::string note;
    if (scene.spec.fit == SceneFit::scale) {
      const FitSize size = scaled_fit_size(width_px, height_px, place.width_px, place.height_px);
      try {
        fitted = scale_image_down(scene.image_cd_m2, size.width_px, size.height_px);
      } catch (const std::invalid_argument& error) {
        throw ConfigError(scene.spec.where, "scenes." + name, "fit = \"scale\": " + std::string(error.what()));
      }
      note = " scaled to ";
    } else {
      fitted = crop_image_centre(scene.image_cd_m2, place.width_px, place.height_px);
      note = " cropped to its centre ";
    }
    note = "scene '" + name + "' (" + size_text(width_px, height_px) + ")" + note +
           size_text(fitted.width_px, fitted.height_px) + " to fit its place (" +
           size_text(place.width_px, place.height_px) + ", fit = \"" + to_string(scene.spec.fit) + "\")";
    scenes.replace_image(name, std::move(fitted), note);
  }
}

}  // namespace glarelab
