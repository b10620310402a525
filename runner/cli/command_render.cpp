// glarelab render: the first stimulus frame a seeded session shows for a condition, as linear EXR
// (cd/m2, after glare, with the question text) or as the display-encoded PNG the screen was sent.
// The frame comes from the session itself (runner/session/stimulus_preview.h), run offscreen with
// the simulated observer on a database thrown away afterwards: the trials before it pass with the
// same clock and eye history, so the preview is what a participant of that number would see, for
// every procedure, per-side glare and overlay. --intensity and --settings show an adaptive track
// or an adjustment at another point than its start. Several conditions (--condition again, or
// --all-conditions) are captured in one pass of the session into a folder (--out-dir).
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/exr_io.h"
#include "core/png_io.h"
#include "protocols/comparison_luminance.h"
#include "protocols/experiment.h"
#include "runner/cli/commands.h"
#include "runner/cli/option_checks.h"
#include "runner/session/session_runner.h"
#include "stimuli/scene_library.h"

namespace glarelab::cli {
namespace {

struct RenderOptions {
  std::string experiment_path;
  std::vector<std::string> conditions;  // --condition, once or more
  bool all_conditions = false;
  std::optional<double> time_s;
  std::string glare;  // empty: the condition's mode
  std::vector<double> intensity_cd_m2;  // at most one value
  std::vector<double> settings_cd_m2;   // two values
  std::optional<int> participant_number;
  std::optional<std::uint64_t> seed;
  std::optional<FrameEngineRequest> engine;  // --engine; nothing: [display] engine
  std::string out;      // one condition: the file
  std::string out_dir;  // any number: the folder, NAME.exr and NAME.png in it
};

void check_condition(const Experiment& experiment, const std::string& name) {
  std::string names;
  for (const ConditionRow& row : experiment.conditions) {
    if (row.name() == name) return;
    names += (names.empty() ? "'" : ", '") + row.name() + "'";
  }
  throw ConfigError({"--condition", 0, 0}, "condition", "unknown condition '" + name + "' (conditions: " + names + ")");
}

// A directory of its own for the preview's database, removed with everything in it.
class ScratchDatabase {
 public:
  ScratchDatabase() {
    std::string pattern = (std::filesystem::temp_directory_path() / "glarelab-render-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw std::filesystem::filesystem_error("render: cannot make a scratch directory", std::filesystem::path(pattern),
                                              std::error_code(errno, std::generic_category()));
    directory_ = pattern;
  }
  ~ScratchDatabase() {
    std::error_code ignored;
    std::filesystem::remove_all(directory_, ignored);
  }
  std::string path() const { return (directory_ / "preview.db").string(); }

 private:
  std::filesystem::path directory_;
};

std::string describe(const PreviewFrame& frame) {
  std::ostringstream text;
  if (!frame.plan.real_stimulus.empty()) {
    text << "trial " << frame.plan.trial_index << " (" << frame.plan.procedure << "), " << frame.glare_label << " at "
         << frame.time_s << " s: the instruction to look at it, no image rendered";
    return text.str();
  }
  text << "trial " << frame.plan.trial_index << " (" << frame.plan.procedure << "), " << frame.glare_label
       << " glare at " << frame.time_s << " s";
  if (frame.plan.intensity && !frame.plan.comparison_positions.empty())
    text << ", comparison at " << *frame.plan.intensity << " cd/m2";
  if (!frame.plan.adjustment_start_cd_m2.empty())
    text << ", spots at " << frame.plan.adjustment_start_cd_m2[0] << " and " << frame.plan.adjustment_start_cd_m2[1]
         << " cd/m2";
  if (frame.reports.empty()) return text.str() + ": no glare computed";
  text << ":";
  for (const GlareFrameReport& report : frame.reports) {
    text << " [" << to_string(report.mode) << " "
         << (report.convolved ? "convolved" : "skipped (" + report.skip_reason + ")") << ", pupil "
         << report.pupil_diameter_mm << " mm, fibre gratings " << (report.gratings_in_pupil ? "in" : "behind")
         << " the pupil, wing fraction " << report.wing_fraction << "]";
  }
  return text.str();
}

// The preview session: offscreen, the simulated observer, a database thrown away.
RunResult run_preview(const RenderOptions& options, const std::vector<std::string>& conditions) {
  const ScratchDatabase scratch;
  RunOptions run;
  run.experiment_path = options.experiment_path;
  run.db_path = scratch.path();
  run.display = "offscreen";
  run.observer = "simulated";
  run.participant = "render";
  run.seed = options.seed;
  run.participant_number = options.participant_number;
  run.engine = options.engine;
  StimulusPreview preview;
  preview.conditions = conditions;
  preview.comparison_cd_m2 = options.intensity_cd_m2.empty() ? options.settings_cd_m2 : options.intensity_cd_m2;
  preview.time_s = options.time_s;
  if (!options.glare.empty()) preview.glare = parse_glare_mode(options.glare);
  run.preview = preview;
  std::ostringstream progress;  // the session's own progress lines are not the preview's
  return run_session(run, progress);
}

// The frame as linear EXR (cd/m2) or as the display-encoded PNG, by the file's extension; written
// beside the file and renamed into place, so a preview stopped mid-write leaves no half an image.
void write_frame(const PreviewFrame& frame, const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension == ".png") {
    ImageRGBA encoded = frame.display_drive;
    for (std::size_t i = 3; i < encoded.rgba.size(); i += 4) encoded.rgba[i] = 1.0f;
    write_through_temporary(path, [&](const std::string& temporary) { write_png_encoded(temporary, encoded); });
  } else {
    // Loadable as a scene with no option (stimuli/scene_library.h: the glare's round-off below 0 set to 0).
    ImageRGBA linear = frame.stimulus_cd_m2;
    zero_round_off_negatives(linear);
    write_through_temporary(path, [&](const std::string& temporary) {
      write_exr(temporary, linear, display_frame_exr_options());
    });
  }
}

// A condition's name as a file name: letters, digits, '.', '-' and '_' kept, anything else '_'.
std::string file_name_of(const std::string& condition) {
  std::string name = condition;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  if (name.empty() || name.front() == '.') name.insert(name.begin(), '_');
  return name;
}

// The conditions asked for, each checked; every row's name for --all-conditions (the rows a
// seeded session shows: render each of the others alone, which shows it as its track would).
std::vector<std::string> asked_conditions(const RenderOptions& options, const Experiment& experiment) {
  if (options.all_conditions) {
    std::vector<std::string> names;
    for (const ConditionRow& row : experiment.conditions)
      if (why_no_session_shows(experiment, row.name()).empty()) names.push_back(row.name());
    return names;
  }
  std::vector<std::string> names;
  for (const std::string& name : options.conditions) {
    check_condition(experiment, name);
    // A row that no session shows (in no block, in no track) has no frame to preview: said before
    // anything runs. Any other row is previewed, a QUEST+ row its track never picks included
    // (protocols/comparison_luminance.h, show_condition_in_preview).
    if (const std::string why = why_no_session_shows(experiment, name); !why.empty())
      throw std::invalid_argument("condition '" + name + "' cannot be previewed: " + why);
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

void check_outputs(const RenderOptions& options, std::size_t conditions) {
  if (options.conditions.empty() && !options.all_conditions)
    throw std::invalid_argument("render: give --condition NAME (once or more) or --all-conditions");
  if (options.out.empty() == options.out_dir.empty())
    throw std::invalid_argument("render: give --out FILE (one condition) or --out-dir FOLDER (any number)");
  if (!options.out.empty() && (options.all_conditions || conditions != 1))
    throw std::invalid_argument("render: --out names one frame's file; for several conditions give --out-dir FOLDER");
  if (!options.intensity_cd_m2.empty() && !options.settings_cd_m2.empty())
    throw std::invalid_argument("--intensity (staircase, QUEST) and --settings (adjustment) exclude each other");
  if ((options.all_conditions || conditions > 1) &&
      (!options.intensity_cd_m2.empty() || !options.settings_cd_m2.empty() || options.time_s || !options.glare.empty()))
    throw std::invalid_argument("render: --intensity, --settings, --time and --glare change the trial shown, and so every "
                                "trial after it: they are for one condition");
}

int render_one(const RenderOptions& options, const std::string& condition) {
  const RunResult result = run_preview(options, {condition});
  const PreviewFrame& frame = result.previews.front();
  write_frame(frame, options.out);
  std::cout << "render: condition '" << condition << "', " << describe(frame) << " -> " << options.out << " ("
            << frame.stimulus_cd_m2.width_px << "x" << frame.stimulus_cd_m2.height_px << ")\n";
  if (!result.preview_note.empty()) std::cout << "  note: " << result.preview_note << "\n";
  for (const std::string& note : result.scene_notes) std::cout << "  note: " << note << "\n";
  return 0;
}

int render_into_folder(const RenderOptions& options, const std::vector<std::string>& conditions) {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> condition_of_file;
  for (const std::string& condition : conditions)
    if (const auto [at, added] = condition_of_file.emplace(file_name_of(condition), condition); !added)
      throw std::invalid_argument("render: conditions '" + at->second + "' and '" + condition + "' would both be written as " +
                                  at->first + ".exr");
  refuse_symbolic_link(options.out_dir, "--out-dir");
  if (const std::optional<std::string> file = file_in_the_way_of_folder(options.out_dir))
    throw std::invalid_argument("--out-dir: " + *file + " is a file, not a folder");
  fs::create_directories(options.out_dir);
  const RunResult result = run_preview(options, conditions);
  for (const PreviewFrame& frame : result.previews) {
    const fs::path base = fs::path(options.out_dir) / file_name_of(frame.plan.condition_name);
    for (const char* extension : {".exr", ".png"}) {
      const std::string path = base.string() + extension;
      refuse_symbolic_link(path, "--out-dir");
      write_frame(frame, path);
    }
    std::cout << "render: condition '" << frame.plan.condition_name << "', " << describe(frame) << " -> " << base.string()
              << ".exr, .png (" << frame.stimulus_cd_m2.width_px << "x" << frame.stimulus_cd_m2.height_px << ")\n";
  }
  for (const std::string& note : result.scene_notes) std::cout << "  note: " << note << "\n";
  std::vector<std::string> missing;
  for (const std::string& condition : conditions)
    if (std::none_of(result.previews.begin(), result.previews.end(),
                     [&](const PreviewFrame& frame) { return frame.plan.condition_name == condition; }))
      missing.push_back(condition);
  std::cout << "render: " << result.previews.size() << " of " << conditions.size() << " conditions written to "
            << options.out_dir << "\n";
  if (missing.empty()) return 0;
  // An adaptive track picks its own rows: one it never picked in this seeded session is shown on
  // its own, as the track would show it.
  std::string listed;
  for (const std::string& condition : missing) listed += (listed.empty() ? "'" : ", '") + condition + "'";
  std::cout << "  note: the seeded session shows no trial of " << listed
            << "; render each alone with --condition NAME --out FILE\n";
  return 0;
}

int render(const RenderOptions& options) {
  // Before the session: a link is refused, not written through.
  if (!options.out.empty()) refuse_symbolic_link(options.out, "--out");
  const Experiment experiment = load_experiment(options.experiment_path);
  const std::vector<std::string> conditions = asked_conditions(options, experiment);
  check_outputs(options, conditions.size());
  if (!options.out.empty()) return render_one(options, conditions.front());
  return render_into_folder(options, conditions);
}

}  // namespace

Action add_render_command(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  auto time_s = std::make_shared<double>(0.0);
  auto participant_number = std::make_shared<int>(1);
  auto seed = std::make_shared<std::uint64_t>(0);
  CLI::App* command = app.add_subcommand(
      "render", "Write the first stimulus frame a seeded session shows for a condition (after glare, with the "
                "question) as linear EXR or a display-encoded PNG");
  command->add_option("experiment", options->experiment_path, "Experiment file (TOML)")->required();
  auto* condition_option = command->add_option(
      "--condition", options->conditions,
      "Condition name (the 'name' column, or 'row N'); again for more conditions, rendered in one pass (--out-dir)");
  command->add_flag("--all-conditions", options->all_conditions,
                    "Every condition the seeded session shows, in one pass (--out-dir)")
      ->excludes(condition_option);
  auto* time_option =
      command->add_option("--time", *time_s,
                          "Compute the glare for this session time (s, at most 86400) instead of the frame's own")
          ->check(eye_model_time_s());
  command->add_option("--glare", options->glare, "Override the condition's glare mode (whole frame)")
      ->check(CLI::IsMember({"dynamic", "static", "control"}));
  command->add_option("--intensity", options->intensity_cd_m2,
                      "Staircase or QUEST: the comparison's peak luminance (cd/m2) instead of the track's start")
      ->expected(1)
      ->check(finite_positive_number("cd/m2"));
  command->add_option("--settings", options->settings_cd_m2,
                      "Adjustment: the left and right spots' luminances (cd/m2) instead of their start")
      ->expected(2)
      ->check(finite_positive_number("cd/m2"));
  auto* participant_option =
      command->add_option("--participant-number", *participant_number,
                          "Participant number (block order) of the session previewed (default: the file's, else 1)")
          ->check(whole_number_check(1, kMaxParticipantNumber));
  auto* seed_option = command->add_option("--seed", *seed, "Seed (overrides the file's)")->check(seed_check());
  auto engine = std::make_shared<FrameEngineRequest>(FrameEngineRequest::automatic);
  auto* engine_option = add_choice_option(command, "--engine", *engine,
                                          "Frame engine: cpu, gpu (OpenGL 4.5: GL glare and GL perception stages) or "
                                          "auto (gpu on a hardware GPU with OpenGL 4.5, else cpu); replaces [display] engine");
  // Checked before anything is rendered: any other name would get EXR bytes under a misleading extension.
  command->add_option("--out", options->out, "Output file: .exr (linear, cd/m2) or .png (display-encoded preview)")
      ->check(file_extension_in({".exr", ".png"}, "the frame file"));
  command->add_option("--out-dir", options->out_dir,
                      "Output folder for one or more conditions: NAME.exr (linear, cd/m2) and NAME.png (display-encoded) each");
  return [=]() {
    if (time_option->count() > 0) options->time_s = *time_s;
    if (participant_option->count() > 0) options->participant_number = *participant_number;
    if (seed_option->count() > 0) options->seed = *seed;
    if (engine_option->count() > 0) options->engine = *engine;
    return report_errors([&]() { return render(*options); });
  };
}

}  // namespace glarelab::cli
