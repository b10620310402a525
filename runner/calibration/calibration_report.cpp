#include "runner/calibration/calibration_report.h"

#include <cstdio>

namespace glarelab {

double CalibrationSummary::additivity_error_percent() const {
  return 100.0 * (white_peak_cd_m2 - table_peak_cd_m2) / table_peak_cd_m2;
}

CalibrationSummary summarise_calibration(const CalibrationPlan& plan, const std::vector<PatchReading>& readings) {
  CalibrationSummary summary;
  for (PatchChannel channel : kPatchChannels) {
    std::vector<double> drive, luminance;
    for (int level = 0; level < plan.levels; ++level) {
      drive.push_back(plan.patch(channel, level).drive);
      luminance.push_back(readings[static_cast<std::size_t>(static_cast<int>(channel) * plan.levels + level)].luminance_cd_m2);
    }
    summary.fits[static_cast<std::size_t>(channel)] = fit_gamma(drive, luminance);
  }
  // The same arithmetic as DisplayCalibration::black_cd_m2 and peak_cd_m2 (core/display_calibration.h).
  for (int c = 0; c < 3; ++c) summary.table_black_cd_m2 += summary.fits[static_cast<std::size_t>(c)].black_cd_m2 / 3.0;
  summary.table_peak_cd_m2 = summary.table_black_cd_m2;
  for (int c = 0; c < 3; ++c)
    summary.table_peak_cd_m2 +=
        summary.fits[static_cast<std::size_t>(c)].peak_cd_m2 - summary.fits[static_cast<std::size_t>(c)].black_cd_m2;
  summary.white_peak_cd_m2 = summary.fits[3].peak_cd_m2;
  return summary;
}

std::string describe_calibration(const CalibrationSummary& summary) {
  std::string text;
  char line[256];
  for (PatchChannel channel : kPatchChannels) {
    const GammaFit& fit = summary.fits[static_cast<std::size_t>(channel)];
    std::snprintf(line, sizeof line, "  %-5s  black %.6g cd/m2  peak %.6g cd/m2  ", to_string(channel), fit.black_cd_m2,
                  fit.peak_cd_m2);
    text += line;
    if (fit.gamma) {
      std::snprintf(line, sizeof line, "gamma %.4f (fitted to %d levels, rms residual %.4f log10)\n", *fit.gamma,
                    fit.points, fit.rms_residual_log10);
    } else {
      std::snprintf(line, sizeof line, "gamma not fitted (%d level(s) above 1%% of the full gain; 2 needed)\n",
                    fit.points);
    }
    text += line;
  }
  std::snprintf(line, sizeof line,
                "  table: black %.6g cd/m2, peak %.6g cd/m2 (black + the three gains); white measured %.6g cd/m2 "
                "(%+.2f %%: additivity)\n",
                summary.table_black_cd_m2, summary.table_peak_cd_m2, summary.white_peak_cd_m2,
                summary.additivity_error_percent());
  text += line;
  return text;
}

}  // namespace glarelab
