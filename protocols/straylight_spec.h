#pragma once
// What a `[procedure] type = "straylight"` measurement shows (docs/STRAYLIGHT.md): the ring, the
// test field, the flicker and the compensation range, as plain data the experiment holds
// (protocols/straylight_config.h reads and checks it).
#include <string>

namespace glarelab {

// The compensation the measurement may show, log10 s_c (deg^2 / sr): from 2 s - 0.3 of an eye
// clearer than any healthy young one (log s 0.6, the age norm 0.87 less 2.7 population SDs) to
// 2 s + 0.3 of dense cataract (log s 2.2); levels outside are shown at the bound.
inline constexpr double kStraylightMinCompensationLog10 = 0.6;
inline constexpr double kStraylightMaxCompensationLog10 = 2.8;
// The steps the fixed levels are shown in (log10 s_c); the encoding must resolve them.
inline constexpr double kStraylightLevelStepLog10 = 0.02;
// How far the flicker may be from the asked frequency once it is a whole, even number of frames
// per cycle (60 Hz: 8 frames, 7.5 Hz for 8 Hz asked, 6 % off).
inline constexpr double kStraylightFlickerTolerance = 0.1;

struct StraylightSpec {
  double ring_inner_deg = 5.0;   // the flickering ring, from its inner to its outer edge (visual angle
  double ring_outer_deg = 10.0;  // from the fixation point); its log-angle mean (7.07 deg) is where s is measured
  // The ring's luminance while on. Unset in the file: the brightest ring whose whole compensation
  // range the display's peak can show (min(peak, peak / (k 10^kStraylightMaxCompensationLog10))).
  double ring_luminance_cd_m2 = 0.0;
  double test_field_radius_deg = 2.0;  // the dark, split test field in the ring's centre
  double flicker_hz = 8.0;             // asked; shown as refresh_hz / frames_per_cycle
  int frames_per_cycle = 8;            // even: half the cycle on, half off
  std::string eye;                     // "left" or "right": the eye tested (the other one covered)
  int answers = 25;                    // range finding and fixed levels together
  // Whole flicker cycles each presentation shows (12: 1.6 s at 7.5 Hz). Reconstructed: the
  // C-Quant's own presentation time is not in the sources this project has (docs/STRAYLIGHT.md).
  int cycles = 12;
  // The display's own stray light on the test field while the ring is on (its glow around a bright
  // ring, read with a photometer at the field's centre with the ring on and the field dark); it
  // flickers with the ring like the eye's straylight and is subtracted from the estimate.
  double display_glow_cd_m2 = 0.0;
};

}  // namespace glarelab
