#pragma once
// The keys of `[procedure] type = "straylight"` (the compensation-comparison measurement,
// docs/STRAYLIGHT.md) and the checks that the display in [display] can show it: a flicker of an
// even whole number of frames per cycle near the asked frequency, a compensation light the
// display's encoding resolves in 0.02 log10 steps over the whole compensation range, and a ring
// inside the display.
#include <string>

#include "core/display_spec.h"
#include "glare/glare_spec.h"
#include "protocols/experiment.h"
#include "protocols/straylight_spec.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// Reads the keys of [procedure] for type "straylight" and checks them against `display`. Throws
// ConfigError at the key's file:line:column (the table's when the key is absent) naming the key.
StraylightSpec read_straylight_procedure(TableReader& procedure, const DisplaySpec& display);

// `[procedure] type = "straylight"`: reads the table into experiment.procedure and
// experiment.straylight (the display is read before) and returns true; false for any other type.
// [scenes], [conditions] and [[blocks]] are refused at their keys, as is a stereo display.
bool read_straylight_design(TableReader& top, Experiment& experiment);
// The [procedure] table of a resolved configuration; read_straylight_design reads it back.
toml::table straylight_procedure_toml(const StraylightSpec& spec);

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

// `[glare] straylight` (glare_config.cpp reads a number): sets experiment.glare to `glare` with the
// observer's eye ([observer]), keeping the straylight, which a CIE eye of the observer's
// pigmentation must be able to have with less than all of the light scattered
// (check_observer_eye); ConfigError at the key otherwise. The string "measured" sets
// experiment.straylight_measured to the key's place: the session takes the participant's most
// recent reliable measurement from its database (runner/session/straylight_session.h).
void set_glare_observer_eye(TableReader& top, Experiment& experiment, GlareSpec glare, const ObserverEye& observer_eye);

}  // namespace glarelab
