#pragma once
// The gamma and peak a calibration reports for each primary and for white, for the gamma model
// with a black offset (the "gain-offset-gamma" family of Brainard, Pelli and Robson 2002, "Display
// characterization", with gain 1 and offset 0 in drive): L(d) = L_black + (L_peak - L_black) d^gamma.
// It is a summary for people: the table itself is used as measured, never this curve.
// Gamma is the least-squares slope of log10(L(d) - L_black) against log10(d) over the levels above
// black whose gain over black is at least kMinFitGainFraction of the full gain: lower levels sit at
// the photometer's noise floor, where the logarithm turns a small absolute error into a large one.
// The intercept is free (the amplitude is not forced to the full-drive reading), so one bad
// full-drive reading does not bend the slope.
#include <optional>
#include <string>
#include <vector>

namespace glarelab {

inline constexpr double kMinFitGainFraction = 0.01;

struct GammaFit {
  double black_cd_m2 = 0.0;  // the drive-0 reading
  double peak_cd_m2 = 0.0;   // the full-drive reading (black included)
  std::optional<double> gamma;  // empty when fewer than two levels qualify
  int points = 0;               // levels the slope was fitted to
  double rms_residual_log10 = 0.0;  // of log10 gain about the fitted line
};

// `drive` in [0, 1] rising from 0 to 1, `luminance_cd_m2` the readings at those drives.
GammaFit fit_gamma(const std::vector<double>& drive, const std::vector<double>& luminance_cd_m2);

}  // namespace glarelab
