#include "runner/cli/display_options.h"

#include "runner/cli/option_checks.h"

namespace glarelab::cli {

void add_display_options(CLI::App* command, DisplayOptions& options, const std::string& default_display) {
  options.display = default_display;
  command->add_option("--display", options.display, "window (a person at the screen) or offscreen (EGL, else OSMesa)")
      ->check(CLI::IsMember(display_kinds()))
      ->capture_default_str();
  command->add_option("--width", options.request.width_px,
                      "Width in pixels (with --fullscreen: the monitor's video mode closest to it)")
      ->check(whole_number_check(1, 16384))
      ->capture_default_str();
  command->add_option("--height", options.request.height_px, "Height in pixels")
      ->check(whole_number_check(1, 16384))
      ->capture_default_str();
  command->add_option("--refresh-hz", options.request.refresh_hz,
                      "Offscreen: the virtual refresh rate (Hz); a window runs at its monitor's rate")
      ->check(finite_number_in(1.0, 1000.0, "Hz"))
      ->capture_default_str();
  command->add_option("--monitor", options.request.monitor, "Window: the monitor's index (0: the primary monitor)")
      ->check(whole_number_check(0, 63))
      ->capture_default_str();
  command->add_flag("--fullscreen", options.request.fullscreen, "Window: full screen on the monitor, at its video mode");
}

}  // namespace glarelab::cli
