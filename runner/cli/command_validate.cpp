#include <iostream>

#include "core/real_stimulus.h"
#include "protocols/experiment.h"
#include "protocols/procedure.h"
#include "runner/cli/commands.h"
#include "runner/session/condition_depth_of_field.h"
#include "runner/session/condition_refraction.h"
#include "runner/session/scene_places.h"
#include "runner/session/session_eyes.h"
#include "stimuli/scene_library.h"

namespace glarelab::cli {

Action add_validate_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* validate = app.add_subcommand("validate", "Check an experiment file and its tables and scenes without running it");
  validate->add_option("experiment", *path, "Experiment file (TOML)")->required();
  return [=]() {
    return report_errors([&]() {
      const Experiment experiment = load_experiment(*path);
      SceneLibrary scenes(experiment.scenes, experiment.display);
      fit_scenes_to_places(experiment, scenes, /*refuse_misfits=*/true);
      const auto procedure = make_procedure(experiment, scenes.peak_luminances_cd_m2());
      // The refusals a session makes for the observer's refraction (the [glare] grid must sample
      // every condition's residual), made here too so a file that validates also runs.
      check_condition_refractions(experiment);
      check_stereo_layout(experiment, scenes);
      check_depth_of_field(experiment, scenes);
      std::cout << *path << ": ok: experiment '" << experiment.name << "', " << experiment.scenes.size()
                << " scene(s), " << experiment.conditions.size() << " condition row(s), " << procedure->planned_trials() << " "
                << experiment.procedure << " trials, display " << experiment.display.width_px << "x"
                << experiment.display.height_px << " at " << experiment.display.refresh_hz << " Hz\n";
      for (const auto& [name, scene] : scenes.scenes()) {
        std::cout << "  scene " << name << ": " << scene.image_cd_m2.width_px << "x" << scene.image_cd_m2.height_px
                  << " px, peak " << scene.peak_cd_m2 << " cd/m2, mean " << scene.mean_cd_m2 << " cd/m2\n";
      }
      for (const std::string& note : scene_load_notes(scenes)) std::cout << "  note: " << note << "\n";
      // Conditions that show a physical object (core/real_stimulus.h): nothing to load for them.
      for (const ConditionRow& row : experiment.conditions)
        if (const std::string* scene = row.find("scene"); scene != nullptr && is_real_stimulus(*scene))
          std::cout << "  real stimulus: condition " << row.name() << " shows the real " << real_stimulus_object(*scene)
                    << " (an instruction, no image)\n";
      for (const ConditionRefraction& refraction : condition_refractions(experiment))
        std::cout << "  refraction: " << describe_condition_refraction(refraction) << "\n";
      return 0;
    });
  };
}

}  // namespace glarelab::cli
