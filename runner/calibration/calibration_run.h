#pragma once
// `glarelab calibrate`: the patches of a calibration plan shown one after another on a display, a
// photometer reading taken for each (typed at the terminal, or all read from a measurements file),
// the calibration CSV written and the fitted gamma and peak reported (docs/DISPLAY_CALIBRATION.md).
// Nothing is written unless every patch has a reading and the readings pass check_readings.
#include <ostream>
#include <string>

#include "runner/display/display_backend.h"

namespace glarelab {

struct CalibrationOptions {
  std::string display = "window";  // window | offscreen | egl | osmesa
  DisplayRequest request;          // size, monitor, fullscreen; bits_per_channel is set from below
  int levels = 17;
  int bits_per_channel = 8;        // 8 or 10 (codes) or 16 (half float)
  double patch_fraction = 1.0;     // of the screen's width and height; 1: the whole screen
  std::string measurements_path;   // empty: read each luminance from the terminal (window only)
  std::string out_path;            // the calibration CSV
  std::string save_patches_dir;    // empty: none; else each patch as drawn (PNG at 8 bits, EXR otherwise)
};

// Returns the exit code: 0 with the CSV written, kExitAborted (Escape, window closed, Ctrl-C, or
// "q" at the terminal) with nothing written. Bad options or readings throw (ConfigError,
// std::invalid_argument: exit 2) before the display opens when they come from a file; typed
// readings that fail the checks are reported and the patch at fault is shown again.
int run_calibration(const CalibrationOptions& options, std::ostream& out);

}  // namespace glarelab
