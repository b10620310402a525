#pragma once
// Per-participant pupil range (Luidolt 2020, Sec. 5.2.1 ii): a black and then a white full screen
// for a few seconds each (5 s in the thesis); the mean pupil during black is the participant's
// largest, during white the smallest. The model pupil is then either the measured diameter or the
// measurement mapped linearly from [white, black] onto the model range 2-8 mm.
#include <optional>
#include <string>
#include <vector>

#include "runner/tracker/pupil_filter.h"

namespace glarelab {

struct PupilRange {
  double smallest_mm = 0.0;  // mean over the white screen
  double largest_mm = 0.0;   // mean over the black screen
  int white_samples = 0;
  int black_samples = 0;
  std::string describe() const;  // "white_mean_mm=... black_mean_mm=... (N, M samples)"
};

// Mean model pupil of the accepted samples in each phase. nullopt with `why` set when a phase has
// no accepted sample or the black mean does not exceed the white mean by at least 0.2 mm.
std::optional<PupilRange> calibrate_pupil_range(const std::vector<FilteredPupil>& black_phase,
                                                const std::vector<FilteredPupil>& white_phase, std::string* why);

// Luidolt 2020, 5.2.1 ii: maps [smallest, largest] linearly onto [2, 8] mm, clamped to that range.
double map_pupil_to_model_range(double measured_mm, const PupilRange& range);

constexpr double kModelPupilMin_mm = 2.0;
constexpr double kModelPupilMax_mm = 8.0;

}  // namespace glarelab
