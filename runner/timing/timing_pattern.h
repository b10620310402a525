#pragma once
// What `glarelab timing-test` shows on each flip, after Psychtoolbox's VBLSyncTest and
// PerceptualVBLSyncTest (docs/TIMING.md):
//  - flicker: the whole screen white on even frames and black on odd ones, so a photodiode on any
//    part of the screen sees one edge per refresh, the first (white) at the first flip;
//  - tearing: white vertical bars on black moving sideways by kTearingStepFraction of the screen's
//    width per frame; a flip that is not synchronised to the retrace shows as a horizontal break
//    across the bars, at a height that wanders from frame to frame.
#include <string>
#include <vector>

namespace glarelab {

enum class TimingPattern { flicker, tearing };
TimingPattern parse_timing_pattern(const std::string& name);  // throws std::invalid_argument
const char* to_string(TimingPattern pattern);
std::vector<std::string> timing_pattern_names();

// Bars one sixteenth of the width wide, one in every eighth; moving a sixty-fourth of the width
// per frame, a bar passes its own width in four frames: fast enough for a break to be obvious.
inline constexpr double kTearingBarFraction = 1.0 / 16.0;
inline constexpr double kTearingPeriodFraction = 1.0 / 8.0;
inline constexpr double kTearingStepFraction = 1.0 / 64.0;

// The left edges (pixels, possibly negative: a bar entering from the left) of the bars of frame k.
std::vector<int> tearing_bar_lefts_px(int width_px, long frame_index);

// Draws frame `frame_index` of `pattern` into the display's frame (`framebuffer`:
// DisplayBackend::frame_framebuffer, 0 the default framebuffer).
void draw_timing_pattern(TimingPattern pattern, long frame_index, int width_px, int height_px, unsigned framebuffer = 0);

}  // namespace glarelab
