#pragma once
// The keys of `[procedure] type = "straylight"` (the compensation-comparison measurement,
// docs/STRAYLIGHT.md) and the checks that the display in [display] can show it: a flicker of an
// even whole number of frames per cycle near the asked frequency, a compensation light the
// display's encoding resolves in 0.02 log10 steps over the whole compensation range, and a ring
// inside the display.
#include <string>

#include "core/display_spec.h"
#include "glare/glare_spec.h"
#include "protocols/toml_table_reader.h"

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
  // The display's own stray light on the test field while the ring is on (its glow around a bright
  // ring, read with a photometer at the field's centre with the ring on and the field dark); it
  // flickers with the ring like the eye's straylight and is subtracted from the estimate.
  double display_glow_cd_m2 = 0.0;
};

// Reads the keys of [procedure] for type "straylight" and checks them against `display`. Throws
// ConfigError at the key's file:line:column (the table's when the key is absent) naming the key.
StraylightSpec read_straylight_procedure(TableReader& procedure, const DisplaySpec& display);

// Frames per cycle of a square-wave flicker near `flicker_hz` at `refresh_hz`: the even whole
// number (at least 2) nearest refresh_hz / flicker_hz.
int straylight_frames_per_cycle(double refresh_hz, double flicker_hz);

// The achromatic luminance (cd/m2) the display shows at a drive level in [0, 1] on every channel:
// the inverse of the encoding the encode pass applies (sRGB, gamma, PQ or the measured table).
double display_luminance_at_drive(const DisplaySpec& display, double drive01);

// The largest step in log10 luminance between neighbouring drive levels of the display's
// framebuffer (bits_per_channel; 0, the backend's default framebuffer, counts as 8 bits; 16, half
// floats, as 11 significant bits) anywhere from `low_cd_m2` to `high_cd_m2`.
double largest_drive_step_log10(const DisplaySpec& display, double low_cd_m2, double high_cd_m2);

// `[glare] straylight` (glare_config.cpp reads it): sets the observer's eye ([observer]) in `spec`,
// keeping the straylight, which a CIE eye of the observer's pigmentation must be able to have with
// less than all of the light scattered (check_observer_eye); ConfigError at the key otherwise.
void set_glare_observer_eye(TableReader& top, GlareSpec& spec, const ObserverEye& observer_eye);

}  // namespace glarelab
