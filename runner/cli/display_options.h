#pragma once
// The display options of the commands that open a display without an experiment file
// (`calibrate`, `timing-test`): which backend, the size, the monitor, full screen, and the refresh
// an offscreen display is timed at.
#include <CLI/CLI.hpp>

#include <string>

#include "runner/display/display_backend.h"

namespace glarelab::cli {

struct DisplayOptions {
  std::string display = "window";
  DisplayRequest request;
};

// Adds --display, --width, --height, --refresh-hz, --monitor and --fullscreen to `command`;
// `default_display` is the backend without --display.
void add_display_options(CLI::App* command, DisplayOptions& options, const std::string& default_display);

}  // namespace glarelab::cli
