#pragma once
// Durations in an experiment file: whole refresh periods (`..._frames`) or seconds (`..._s`, rounded
// to the nearest whole number of frames; the runner logs each rounding as a 'duration_rounding'
// session event). A stimulus shorter than one frame cannot be shown and is an error; the other
// timed phases ([presentation]: fixation, inter-stimulus interval, ...) may also be zero (absent).
#include <optional>
#include <string>
#include <string_view>

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

// A duration given as `frames_key` (integer) or `seconds_key` (number), not both; `frames` keeps
// `fallback` when neither is present. With `zero_allowed`, 0 frames (or 0 s) means "none"; a
// positive number of seconds below one frame is still an error. Errors name the key.
FrameCount read_frame_count(TableReader& reader, std::string_view frames_key, std::string_view seconds_key,
                            double refresh_hz, FrameCount fallback, bool zero_allowed);

// The duration_rounding text for one duration ("fixation_duration_s 0.1 s -> 6 frames = ...");
// empty when it was given in frames.
std::string describe_rounding(std::string_view seconds_key, const FrameCount& count, double refresh_hz);

}  // namespace glarelab
