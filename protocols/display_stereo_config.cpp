#include "protocols/display_stereo_config.h"

#include <optional>
#include <string>

namespace glarelab {

// [display] stereo = "none" | "side_by_side" (stimuli/stereo_layout.h). Each eye sees half the
// width: an odd width would give the eyes views of different sizes, so it is refused. Whether the
// scenes fit an eye's half is checked when they are loaded (their sizes are in the files).
void read_display_stereo(TableReader& reader, Experiment& experiment) {
  DisplaySpec& display = experiment.display;
  const std::optional<std::string> stereo = reader.string("stereo");
  if (!stereo) return;
  experiment.stereo_where = reader.value_location("stereo");
  if (*stereo == "none") {
    display.stereo = StereoMode::none;
  } else if (*stereo == "side_by_side") {
    display.stereo = StereoMode::side_by_side;
    if (display.width_px % 2 != 0)
      reader.fail("stereo", "side_by_side gives each eye half of width_px, so width_px must be even, found " +
                                std::to_string(display.width_px));
  } else {
    reader.fail("stereo", "must be \"none\" or \"side_by_side\", found \"" + *stereo + "\"");
  }
}

// Where a study is shown when `run` is given no --display (docs/STEREO.md): a study made for a
// headset says so; the flag wins, so the same file still runs offscreen in a test.
void read_display_output(TableReader& reader, Experiment& experiment) {
  const std::optional<std::string> output = reader.string("output");
  if (!output) return;
  if (*output != "window" && *output != "openxr")
    reader.fail("output", "must be \"window\" or \"openxr\" (a head-mounted display), found \"" + *output + "\"");
  experiment.display_output = *output;
  experiment.display_output_where = reader.value_location("output");
}

}  // namespace glarelab
