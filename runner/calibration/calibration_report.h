#pragma once
// What `glarelab calibrate` reports after a calibration: per primary and for white the black, the
// full-drive luminance (peak) and the fitted gamma (runner/calibration/gamma_fit.h), and the
// additivity check: the table's peak (black + the three primaries' gains, what `encoding =
// "table"` takes as white) against the white actually measured.
#include <array>
#include <string>
#include <vector>

#include "runner/calibration/calibration_measurements.h"
#include "runner/calibration/gamma_fit.h"

namespace glarelab {

struct CalibrationSummary {
  std::array<GammaFit, 4> fits;  // red, green, blue, white (kPatchChannels' order)
  double table_black_cd_m2 = 0.0;  // mean of the three primaries' drive-0 readings
  double table_peak_cd_m2 = 0.0;   // table black + sum of the primaries' gains
  double white_peak_cd_m2 = 0.0;   // measured white at full drive
  // (measured white - table peak) / table peak, in percent.
  double additivity_error_percent() const;
};

// The readings must have passed check_readings.
CalibrationSummary summarise_calibration(const CalibrationPlan& plan, const std::vector<PatchReading>& readings);

// The terminal lines: one row per channel ("red    black 0.2 cd/m2  peak 53.1 cd/m2  gamma 2.200
// (15 levels, rms 0.0000 log10)"), then the additivity line.
std::string describe_calibration(const CalibrationSummary& summary);

}  // namespace glarelab
