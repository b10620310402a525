#pragma once
// Stimulus duration in an experiment file: `stimulus_frames` (whole refresh periods) or
// `stimulus_duration_s` (rounded to the nearest whole number of frames; the runner logs the
// rounding as a 'duration_rounding' session event). A duration shorter than one frame cannot be
// shown and is an error.
#include <string>

#include "protocols/experiment.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Nearest whole number of frames for duration_s at refresh_hz; std::invalid_argument when the
// duration is shorter than one refresh period.
int duration_to_frames(double duration_s, double refresh_hz);

// Reads stimulus_frames or stimulus_duration_s (not both) of [procedure] into spec.
void read_stimulus_duration(TableReader& procedure, double refresh_hz, ForcedChoiceSpec& spec);

// "stimulus_duration_s 0.1 s -> 6 frames = 0.1 s at 60 Hz (rounding error +0 ms)": the text of the
// duration_rounding event; empty when the file gave frames.
std::string describe_duration_rounding(const ForcedChoiceSpec& spec, double refresh_hz);

}  // namespace glarelab
