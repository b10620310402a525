#pragma once
// Procedural eyelids and eyelashes (Ritschel et al. 2009, section 3.6; Kakimoto et al. 2004 used
// bitmaps, here they are geometry, so no asset files).
//  - Lids: two polygons whose margins are parabolas y = y_c -+ x^2 / (2 R) (a 30 mm x 10 mm
//    palpebral fissure). Closure c in [0, 1] moves the margin centres linearly from their open heights
//    to the meeting height (overlapping by 0.2 mm at c = 1, so nothing leaks through a closed eye).
//  - Blinks: one per blink_mean_interval_s at a uniform random offset; closure rises over the closing
//    phase, holds, and falls over the slower opening phase, each with a half-cosine profile.
//  - Squint: a constant closure; the lid closure is squint + (1 - squint) * blink.
//  - Or blinks from outside: after set_recorded_blinks() the schedule is off and the lids follow
//    recorded onsets and offsets (an eye tracker's detected blinks): closing from each onset with the
//    same profile, held closed until the offset (or until the closing phase ends, if later), then
//    opening. Overlapping blinks take the larger closure, so the lids never jump open.
//  - Lashes: opaque line segments rooted on each margin, reaching into the opening by a random
//    overhang (their projection along the axis), moving with the lids.
#include <cstdint>
#include <utility>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/eye_parameters.h"

namespace glarelab {

class EyelidModel {
 public:
  EyelidModel(const EyeParameters& parameters, std::uint64_t seed);

  // Blink closure alone, 0 (open) .. 1 (closed).
  double blink_closure(double time_s) const;
  // Lid closure including the constant squint.
  double lid_closure(double time_s) const;
  // Onset of the blink of interval `index` (blink k starts in [k I, (k + 1) I - duration]).
  double blink_onset_s(std::int64_t index) const;
  double blink_duration_s() const { return closing_s_ + closed_s_ + opening_s_; }
  // Blink of interval `index` of the schedule: closure > 0 exactly on (onset, onset + duration).
  double blink_end_s(std::int64_t index) const { return blink_onset_s(index) + blink_duration_s(); }

  // Recorded blinks replace the schedule from now on: every blink so far, each (onset_s, offset_s)
  // with offset_s +infinity while still closed, onsets ascending. An empty list keeps the lids open.
  void set_recorded_blinks(std::vector<std::pair<double, double>> blinks);
  bool uses_recorded_blinks() const { return recorded_; }

  double upper_margin_centre_mm(double closure) const;
  double lower_margin_centre_mm(double closure) const;
  // Lid polygons and lashes for a lid closure.
  void append_occluders(double closure, ApertureGeometry& geometry) const;

 private:
  struct Lash {
    double root_x_mm;
    double tilt_rad;
    double overhang_mm;
    bool upper;
  };
  EyeParameters parameters_;
  std::uint64_t seed_;
  double closing_s_, closed_s_, opening_s_, interval_s_;
  std::vector<Lash> lashes_;
  bool recorded_ = false;
  struct RecordedBlink {
    double onset_s, offset_s;
  };
  std::vector<RecordedBlink> recorded_blinks_;
  double recorded_closure(const RecordedBlink& blink, double time_s) const;
};

}  // namespace glarelab
