#include "runner/calibration/gamma_fit.h"

#include <cmath>

namespace glarelab {

GammaFit fit_gamma(const std::vector<double>& drive, const std::vector<double>& luminance_cd_m2) {
  GammaFit fit;
  if (drive.empty() || drive.size() != luminance_cd_m2.size()) return fit;
  fit.black_cd_m2 = luminance_cd_m2.front();
  fit.peak_cd_m2 = luminance_cd_m2.back();
  const double full_gain = fit.peak_cd_m2 - fit.black_cd_m2;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < drive.size(); ++i) {
    const double gain = luminance_cd_m2[i] - fit.black_cd_m2;
    if (drive[i] <= 0.0 || !(full_gain > 0.0) || gain < kMinFitGainFraction * full_gain) continue;
    x.push_back(std::log10(drive[i]));
    y.push_back(std::log10(gain));
  }
  fit.points = static_cast<int>(x.size());
  if (x.size() < 2) return fit;
  const double n = static_cast<double>(x.size());
  double mean_x = 0.0, mean_y = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mean_x += x[i] / n;
    mean_y += y[i] / n;
  }
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mean_x) * (x[i] - mean_x);
    sxy += (x[i] - mean_x) * (y[i] - mean_y);
  }
  if (!(sxx > 0.0)) return fit;
  const double slope = sxy / sxx;
  const double intercept = mean_y - slope * mean_x;
  double squares = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double residual = y[i] - (intercept + slope * x[i]);
    squares += residual * residual;
  }
  fit.gamma = slope;
  fit.rms_residual_log10 = std::sqrt(squares / n);
  return fit;
}

}  // namespace glarelab
