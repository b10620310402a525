// glarelab calibrate: the patches a photometer needs, shown in sequence (red, green, blue and
// white, each at --levels drives from black to full), the readings typed at the terminal or read
// from --measurements, the calibration CSV that `encoding = "table"` reads written to --out, and
// the fitted gamma and peak of each channel reported (docs/DISPLAY_CALIBRATION.md).
#include <iostream>
#include <memory>

#include "runner/calibration/calibration_run.h"
#include "runner/cli/commands.h"
#include "runner/cli/display_options.h"
#include "runner/cli/option_checks.h"

namespace glarelab::cli {

Action add_calibrate_command(CLI::App& app) {
  auto options = std::make_shared<CalibrationOptions>();
  auto display = std::make_shared<DisplayOptions>();
  CLI::App* command = app.add_subcommand(
      "calibrate", "Show the patches a photometer measures (red, green, blue, white at rising drives), take the "
                   "readings and write the calibration CSV of encoding = \"table\", with the fitted gamma and peak");
  add_display_options(command, *display, "window");
  command->add_option("--levels", options->levels, "Drive levels per channel, evenly spaced from 0 to full drive")
      ->check(whole_number_check(2, 1024))
      ->capture_default_str();
  command->add_option("--bits-per-channel", options->bits_per_channel,
                      "Framebuffer depth the levels are sent at: 8 or 10 (whole codes) or 16 (half float)")
      ->check(CLI::IsMember({8, 10, 16}))
      ->capture_default_str();
  command->add_option("--patch-fraction", options->patch_fraction,
                      "The patch's share of the screen's width and height, centred on black (1: the whole screen)")
      ->check(finite_number_in(0.01, 1.0, ""))
      ->capture_default_str();
  command->add_option("--measurements", options->measurements_path,
                      "Luminances (cd/m2) of every patch in the order shown, one per line, instead of typing them");
  command->add_option("--out", options->out_path, "The calibration CSV to write")
      ->required()
      ->check(file_extension_in({".csv"}, "the calibration file"));
  command->add_option("--save-patches", options->save_patches_dir,
                      "Directory to save each patch as drawn (PNG at 8 bits, EXR of the drive values otherwise)");
  return [=]() {
    options->display = display->display;
    options->request = display->request;
    options->request.title = "glarelab: calibrate";
    return report_errors([&]() { return run_calibration(*options, std::cout); });
  };
}

}  // namespace glarelab::cli
