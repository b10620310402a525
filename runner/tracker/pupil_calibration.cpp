#include "runner/tracker/pupil_calibration.h"

#include <algorithm>
#include <sstream>

namespace glarelab {

namespace {
// Below this difference the two screens did not move the pupil: the tracker or the screens failed.
constexpr double kMinimumRange_mm = 0.2;

std::optional<double> mean_accepted(const std::vector<FilteredPupil>& phase, int* count) {
  double sum = 0.0;
  *count = 0;
  for (const FilteredPupil& sample : phase) {
    if (!sample.accepted) continue;
    sum += sample.eye_pupil_mm;
    ++*count;
  }
  if (*count == 0) return std::nullopt;
  return sum / *count;
}
}  // namespace

std::string PupilRange::describe() const {
  std::ostringstream text;
  text.precision(6);
  text << "white_mean_mm=" << smallest_mm << " black_mean_mm=" << largest_mm << " (" << white_samples << " and "
       << black_samples << " accepted samples)";
  return text.str();
}

std::optional<PupilRange> calibrate_pupil_range(const std::vector<FilteredPupil>& black_phase,
                                                const std::vector<FilteredPupil>& white_phase, std::string* why) {
  PupilRange range;
  const auto black = mean_accepted(black_phase, &range.black_samples);
  const auto white = mean_accepted(white_phase, &range.white_samples);
  if (!black || !white) {
    *why = std::string("no accepted pupil samples during the ") + (!black ? "black" : "white") + " screen";
    return std::nullopt;
  }
  range.largest_mm = *black;
  range.smallest_mm = *white;
  if (range.largest_mm - range.smallest_mm < kMinimumRange_mm) {
    *why = "the pupil did not respond to the screens (" + range.describe() + ")";
    return std::nullopt;
  }
  return range;
}

double map_pupil_to_model_range(double measured_mm, const PupilRange& range) {
  const double fraction = (measured_mm - range.smallest_mm) / (range.largest_mm - range.smallest_mm);
  return std::clamp(kModelPupilMin_mm + fraction * (kModelPupilMax_mm - kModelPupilMin_mm), kModelPupilMin_mm,
                    kModelPupilMax_mm);
}

}  // namespace glarelab
