#include "runner/session/session_eyes.h"

#include <string>
#include <utility>

#include "core/errors.h"
#include "protocols/procedure.h"
#include "runner/session/condition_refraction.h"

namespace glarelab {

// Each eye's dynamic eye starts adapted to the display's background, what the participant saw
// before the session's first stimulus frame (docs/PERCEPTION.md, "One eye per session"), as its
// perception eye does (stimuli/session_perception.cpp), not adapted to that frame's mean.
SessionEye::SessionEye(const EyeView& eye_view, const Experiment& experiment, GlContextFactory gl_context)
    : view(eye_view),
      own_tracker_samples(true),
      display(eye_display(experiment.display, eye_view)),
      seed(eye_seed(experiment.seed, eye_view.tracker_eye)),
      engine(experiment.glare, experiment.perception.adaptation_time_constants, display, seed, std::move(gl_context),
             experiment.engine) {
  engine.glare().set_dynamic_eye_start(display.background_cd_m2);
}

SessionEye::SessionEye(const Experiment& experiment, int frame_width_px, int frame_height_px,
                       GlContextFactory gl_context)
    : view{0, "", {0, 0, frame_width_px, frame_height_px}},
      display(experiment.display),
      seed(experiment.seed),
      engine(experiment.glare, experiment.perception.adaptation_time_constants, display, seed, std::move(gl_context),
             experiment.engine) {
  engine.glare().set_dynamic_eye_start(display.background_cd_m2);
}

std::vector<std::unique_ptr<SessionEye>> make_session_eyes(const Experiment& experiment, int frame_width_px,
                                                           int frame_height_px, GlContextFactory gl_context) {
  std::vector<std::unique_ptr<SessionEye>> eyes;
  for (const EyeView& view : stereo_eye_views(experiment.display))
    eyes.push_back(std::make_unique<SessionEye>(view, experiment, gl_context));
  if (eyes.empty()) eyes.push_back(std::make_unique<SessionEye>(experiment, frame_width_px, frame_height_px, gl_context));
  return eyes;
}

void check_stereo_layout(const Experiment& experiment, const SceneLibrary& scenes) {
  if (experiment.display.stereo == StereoMode::none) return;
  // How many scenes a trial shows side by side: the procedure's first plan tells (every plan of a
  // procedure shows the same number); a sequential forced choice shows them one at a time.
  const std::unique_ptr<Procedure> procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
  std::size_t shown = procedure->finished() ? 0 : procedure->next_trial().scenes.size();
  // (The session reads `layout` whatever the procedure; others keep its default.)
  if (experiment.forced_choice.layout == "sequential" && shown > 0) shown = 1;
  if (shown == 0) return;
  for (const auto& [name, scene] : scenes.scenes()) {
    const PixelRect size{0, 0, scene.image_cd_m2.width_px, scene.image_cd_m2.height_px};
    const std::string misfit =
        stereo_misfit(experiment.display, std::vector<PixelRect>(shown, size), std::vector<std::string>(shown, name));
    if (!misfit.empty()) throw ConfigError(experiment.stereo_where, "display.stereo", misfit);
  }
  for (const ConditionRefraction& refraction : condition_refractions(experiment))
    if (refraction.traced_lens)
      throw ConfigError(experiment.stereo_where, "display.stereo",
                        "condition '" + refraction.condition + "' looks through spectacles '" + refraction.spectacles +
                            "', whose lens is traced about the display's centre, not about each eye's view: "
                            "stereo = \"side_by_side\" cannot show it");
}

}  // namespace glarelab
