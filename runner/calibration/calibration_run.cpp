#include "runner/calibration/calibration_run.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/png_io.h"
#include "runner/calibration/calibration_measurements.h"
#include "runner/calibration/calibration_plan.h"
#include "runner/calibration/calibration_report.h"
#include "runner/calibration/patch_drawing.h"
#include "runner/calibration/terminal_lines.h"
#include "runner/session/interrupt.h"

namespace glarelab {
namespace {

// Draws a patch into the back buffer and, the first time it is drawn, saves it as drawn.
class PatchPresenter {
 public:
  PatchPresenter(DisplayBackend& display, const CalibrationOptions& options, const CalibrationPlan& plan)
      : display_(display), options_(options), plan_(plan), saved_(plan.patches.size(), false) {
    if (!options_.save_patches_dir.empty()) std::filesystem::create_directories(options_.save_patches_dir);
  }

  void show(std::size_t index) {
    const CalibrationPatch& patch = plan_.patches[index];
    draw_calibration_patch(display_.width_px(), display_.height_px(), options_.patch_fraction, patch.rgb_drive(),
                           display_.frame_framebuffer());
    if (!options_.save_patches_dir.empty() && !saved_[index]) {
      save(index, read_default_framebuffer(display_.width_px(), display_.height_px(), display_.frame_framebuffer()));
      saved_[index] = true;
    }
    display_.present();
  }

 private:
  void save(std::size_t index, ImageRGBA image) {
    const CalibrationPatch& patch = plan_.patches[index];
    char name[64];
    // 8-bit codes fit a PNG exactly; 10-bit codes and half-float drives need the EXR's floats.
    std::snprintf(name, sizeof name, "%03zu_%s_level%02d.%s", index, to_string(patch.channel), patch.level,
                  plan_.bits_per_channel == 8 ? "png" : "exr");
    const std::string path = (std::filesystem::path(options_.save_patches_dir) / name).string();
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 1.0f;
    // Beside and renamed (core/atomic_file.h): an interrupted run leaves no half-written patch.
    if (plan_.bits_per_channel == 8)
      write_through_temporary(path, [&](const std::string& partial) { write_png_encoded(partial, image); });
    else
      write_exr(path, image);
  }

  DisplayBackend& display_;
  const CalibrationOptions& options_;
  const CalibrationPlan& plan_;
  std::vector<bool> saved_;
};

std::optional<std::string> stop_reason(DisplayBackend& display, const std::vector<InputEvent>& input) {
  if (interrupt_requested()) return "interrupted";
  if (display.close_requested()) return "window closed";
  for (const InputEvent& event : input)
    if (event.name == "escape") return "Escape pressed";
  return std::nullopt;
}

std::optional<double> parse_luminance(const std::string& text) {
  double value = 0.0;
  const char* begin = text.data();
  const char* end = begin + text.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  if (text.empty() || error != std::errc() || stop != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::string trim(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// Every patch once, one refresh each: the readings came from a file.
std::optional<std::string> show_all_patches(DisplayBackend& display, PatchPresenter& presenter, std::size_t patches) {
  for (std::size_t i = 0; i < patches; ++i) {
    presenter.show(i);
    if (auto reason = stop_reason(display, display.poll_input())) return reason;
  }
  return std::nullopt;
}

// The person at the photometer: each patch stays on the screen until its reading is typed at the
// terminal (or Space/Enter in the window moves on from a patch already read); Backspace in the
// window (or "b") goes back one patch to measure it again; Escape (or "q") stops without writing.
// Returns the readings, or the reason it stopped.
std::optional<std::string> read_patches_interactively(DisplayBackend& display, PatchPresenter& presenter,
                                                      const CalibrationPlan& plan, std::vector<PatchReading>& readings,
                                                      std::ostream& out) {
  std::vector<std::optional<double>> typed(plan.patches.size());
  TerminalLines terminal;
  std::size_t current = 0;
  bool prompted = false;
  out << "calibrate: aim the photometer at the patch; type each luminance in cd/m2 and Enter. In the window: "
         "Space/Enter next, Backspace previous, Escape stops without writing (at the terminal: b, q).\n";
  while (true) {
    if (!prompted) {
      out << "[" << current + 1 << "/" << plan.patches.size() << "] " << plan.describe(plan.patches[current]);
      if (typed[current]) out << " (was " << *typed[current] << ")";
      out << ": luminance cd/m2? " << std::flush;
      prompted = true;
    }
    presenter.show(current);
    const std::vector<InputEvent> input = display.poll_input();
    if (auto reason = stop_reason(display, input)) return reason;
    // What the window's keys and one typed line ask for, done in order.
    enum class Step { next, back };
    std::vector<Step> steps;
    for (const InputEvent& event : input) {
      if (event.name == "space" || event.name == "enter") steps.push_back(Step::next);
      if (event.name == "backspace") steps.push_back(Step::back);
    }
    if (const std::optional<std::string> raw = terminal.poll()) {
      const std::string line = trim(*raw);
      if (line == "q" || line == "quit") return std::string("quit at the terminal");
      if (line == "b" || line == "back") {
        steps.push_back(Step::back);
      } else if (line.empty()) {
        steps.push_back(Step::next);
      } else if (const std::optional<double> value = parse_luminance(line); value && *value >= 0.0) {
        typed[current] = *value;
        steps.push_back(Step::next);
      } else {
        out << "  '" << line << "' is not a luminance (a number >= 0 in cd/m2); type it again: " << std::flush;
      }
    }
    for (const Step step : steps) {
      prompted = false;
      if (step == Step::back) {
        if (current > 0) --current;
        continue;
      }
      if (!typed[current]) {
        out << "\n  no luminance typed for this patch yet\n";
        break;
      }
      if (++current < plan.patches.size()) continue;
      readings.clear();
      for (const std::optional<double>& value : typed) readings.push_back({*value, 0, 0});
      const std::optional<ReadingProblem> problem = check_readings(plan, readings, "");
      if (!problem) return std::nullopt;
      out << "\ncalibrate: " << problem->message << ": measure it again\n";
      current = problem->patch_index;
      break;
    }
  }
}

// Written beside and renamed into place (core/atomic_file.h): an interrupted calibration leaves the
// previous file whole, and a link standing at --out is refused rather than written through.
void write_text_file(const std::string& path, const std::string& text) {
  refuse_symbolic_link(path, "--out");
  const std::filesystem::path file(path);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  write_file_atomically(path, text);
}

}  // namespace

int run_calibration(const CalibrationOptions& options, std::ostream& out) {
  install_interrupt_handlers();
  if (!options.out_path.empty()) refuse_symbolic_link(options.out_path, "--out");  // before anything is shown
  const CalibrationPlan plan = make_calibration_plan(options.levels, options.bits_per_channel);
  if (!(options.patch_fraction > 0.0 && options.patch_fraction <= 1.0))
    throw std::invalid_argument("calibrate: --patch-fraction must be in (0, 1]");
  // Readings from a file are checked before anything is shown or written.
  std::vector<PatchReading> readings;
  const bool interactive = options.measurements_path.empty();
  if (!interactive) {
    readings = read_measurements_file(options.measurements_path);
    if (const std::optional<ReadingProblem> problem = check_readings(plan, readings, options.measurements_path)) {
      const PatchReading* at = readings.size() == plan.patches.size() ? &readings[problem->patch_index] : nullptr;
      throw ConfigError({options.measurements_path, at != nullptr ? at->line : 0, at != nullptr ? at->column : 0},
                        "measurements", problem->message);
    }
  } else if (options.display != "window") {
    throw std::invalid_argument("calibrate: a " + options.display +
                                " display has nobody reading a photometer at it: give --measurements FILE");
  }

  DisplayRequest request = options.request;
  request.bits_per_channel = options.bits_per_channel;
  const std::unique_ptr<DisplayBackend> display = create_display(options.display, request);
  out << "calibrate: " << plan.levels << " levels x 4 patches (red, green, blue, white) at " << plan.bits_per_channel
      << " bits per channel, " << (options.patch_fraction >= 1.0 ? "full screen" : "centred patch on black") << ", on "
      << display->kind() << " " << display->width_px() << "x" << display->height_px() << " ("
      << display->gl_info().describe() << ")\n";
  PatchPresenter presenter(*display, options, plan);
  const std::optional<std::string> stopped =
      interactive ? read_patches_interactively(*display, presenter, plan, readings, out)
                  : show_all_patches(*display, presenter, plan.patches.size());
  if (stopped) {
    out << "\ncalibrate: stopped (" << *stopped << "): nothing written\n";
    return kExitAborted;
  }

  const std::string comment = "Display calibration by glarelab calibrate: " + std::to_string(plan.levels) +
                              " levels, " + std::to_string(plan.bits_per_channel) + " bits per channel, " +
                              (options.patch_fraction >= 1.0 ? std::string("full-screen patches")
                                                             : "centred patches of " +
                                                                   std::to_string(options.patch_fraction) +
                                                                   " of the screen on black") +
                              ", on " + display->gl_info().renderer;
  write_text_file(options.out_path, calibration_csv(plan, readings, comment));
  out << "calibrate: wrote " << options.out_path << "\n" << describe_calibration(summarise_calibration(plan, readings));
  return 0;
}

}  // namespace glarelab
