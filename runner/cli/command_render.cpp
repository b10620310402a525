// glarelab render: one stimulus frame of a condition at a time, after its glare (stimuli/
// glare_stage.h), as linear EXR (cd/m2) or as a display-encoded PNG preview. The frame is composed
// exactly as a session composes it (offscreen GL, scene_a on the left, scene_b on the right).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>

#include "protocols/experiment.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/display/compute_context.h"
#include "runner/display/display_backend.h"
#include "stimuli/display_model.h"
#include "core/exr_io.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/glare_stage.h"
#include "stimuli/layout.h"
#include "core/png_io.h"
#include "stimuli/scene_library.h"

namespace glarelab::cli {
namespace {

struct RenderOptions {
  std::string experiment_path;
  std::string condition;
  double time_s = 0.0;
  std::string glare;  // empty: the condition's mode
  std::string out;
};

const ConditionRow& find_condition(const Experiment& experiment, const std::string& name) {
  std::string names;
  for (const ConditionRow& row : experiment.conditions) {
    if (row.name() == name) return row;
    names += (names.empty() ? "'" : ", '") + row.name() + "'";
  }
  throw ConfigError({"--condition", 0, 0}, "condition", "unknown condition '" + name + "' (conditions: " + names + ")");
}

ImageRGBA compose(const Experiment& experiment, const ConditionRow& row) {
  const SceneLibrary scenes(experiment.scenes);
  DisplayRequest request;
  request.width_px = experiment.display.width_px;
  request.height_px = experiment.display.height_px;
  request.refresh_hz = experiment.display.refresh_hz;
  request.title = "glarelab render";
  const std::unique_ptr<DisplayBackend> display = create_display("offscreen", request);
  FrameRenderer renderer(display->width_px(), display->height_px());
  std::vector<SceneTexture> textures;
  std::vector<PixelRect> sizes;
  for (const char* column : {"scene_a", "scene_b"}) {
    const LoadedScene& scene = scenes.get(*row.find(column));
    textures.push_back(renderer.upload(scene.image_cd_m2));
    sizes.push_back({0, 0, scene.image_cd_m2.width_px, scene.image_cd_m2.height_px});
  }
  std::vector<PixelRect> columns;
  const std::vector<PixelRect> rects = side_by_side_layout(display->width_px(), display->height_px(), sizes, &columns);
  std::vector<Placement> placements;
  for (std::size_t i = 0; i < textures.size(); ++i) placements.push_back({&textures[i], 1.0, rects[i], columns[i]});
  renderer.compose(placements, experiment.display.background_cd_m2);
  return renderer.read_stimulus();
}

int render(const RenderOptions& options) {
  const Experiment experiment = load_experiment(options.experiment_path);
  const ConditionRow& row = find_condition(experiment, options.condition);
  const GlareMode mode = options.glare.empty() ? glare_mode_for(experiment.glare, row) : parse_glare_mode(options.glare);
  const ImageRGBA composed = compose(experiment, row);
  GlareStage stage(experiment.glare, experiment.display, experiment.seed, gl::compute_context_factory());
  GlareFrameReport report;
  ImageRGBA frame = stage.apply(composed, mode, options.time_s, &report);

  std::string extension = std::filesystem::path(options.out).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension == ".png") {
    const DisplayModel model(experiment.display);
    for (std::size_t i = 0; i < frame.rgba.size(); ++i)
      frame.rgba[i] = i % 4 == 3 ? 1.0f : static_cast<float>(model.encode(frame.rgba[i]));
    write_png_encoded(options.out, frame);
  } else {
    write_exr(options.out, frame);
  }
  std::cout << "render: condition '" << row.name() << "', " << to_string(mode) << " glare at " << options.time_s
            << " s: ";
  if (mode == GlareMode::control)
    std::cout << "no glare";
  else
    std::cout << (report.convolved ? "convolved" : "skipped (" + report.skip_reason + ")") << ", pupil "
              << report.pupil_diameter_mm << " mm, fibre gratings " << (report.gratings_in_pupil ? "in" : "behind")
              << " the pupil, PSF grid " << experiment.glare.grid_px << ", wing fraction " << report.wing_fraction;
  std::cout << " -> " << options.out << " (" << frame.width_px << "x" << frame.height_px << ")\n";
  return 0;
}

}  // namespace

Action add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Write one stimulus frame of a condition (with its glare) as "
                                                   "linear EXR or a PNG preview");
  command->add_option("experiment", options->experiment_path, "Experiment file (TOML)")->required();
  command->add_option("--condition", options->condition, "Condition name (the 'name' column, or 'row N')")->required();
  command->add_option("--time", options->time_s, "Session time of the frame (s), at most 86400 (24 h)")
      ->check(eye_model_time_s())->capture_default_str();
  command->add_option("--glare", options->glare, "Override the condition's glare mode")
      ->check(CLI::IsMember({"dynamic", "static", "control"}));
  // Checked before anything is rendered: any other name would get EXR bytes under a misleading extension.
  command->add_option("--out", options->out, "Output file: .exr (linear, cd/m2) or .png (display-encoded preview)")
      ->required()
      ->check(file_extension_in({".exr", ".png"}, "the frame file"));
  return [=]() { return report_errors([&]() { return render(*options); }); };
}

}  // namespace glarelab::cli
