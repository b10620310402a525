#include "stimuli/perception/lab_colour.h"

#include <cmath>

namespace glarelab {
namespace {

constexpr auto& kRgbToXyz = kRec709ToXyz;
constexpr auto& kXyzToRgb = kXyzToRec709;
// The white of R = G = B = 1: rows of kRgbToXyz summed.
constexpr double kWhiteX = kRgbToXyz[0][0] + kRgbToXyz[0][1] + kRgbToXyz[0][2];
constexpr double kWhiteY = kRgbToXyz[1][0] + kRgbToXyz[1][1] + kRgbToXyz[1][2];
constexpr double kWhiteZ = kRgbToXyz[2][0] + kRgbToXyz[2][1] + kRgbToXyz[2][2];

constexpr double kDelta = 6.0 / 29.0;

double lab_f(double t) {
  if (t > kDelta * kDelta * kDelta) return std::cbrt(t);
  return t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}

double lab_f_inverse(double f) {
  if (f > kDelta) return f * f * f;
  return 3.0 * kDelta * kDelta * (f - 4.0 / 29.0);
}

// f(t) - 4/29 and its inverse, without forming f on the linear branch.
double f_offset(double t) { return t > kDelta * kDelta * kDelta ? std::cbrt(t) - 4.0 / 29.0 : t / (3.0 * kDelta * kDelta); }
double t_of_f_offset(double g) {
  const double f = g + 4.0 / 29.0;
  return f > kDelta ? f * f * f : 3.0 * kDelta * kDelta * g;
}

}  // namespace

void replace_lab_lightness(float* rgb, double lightness, double reference_white_cd_m2) {
  const double white[3] = {kWhiteX, kWhiteY, kWhiteZ};
  const double scale = reference_white_cd_m2 / kWhiteY;
  double relative[3];
  for (int r = 0; r < 3; ++r)
    relative[r] = (kRgbToXyz[r][0] * rgb[0] + kRgbToXyz[r][1] * rgb[1] + kRgbToXyz[r][2] * rgb[2]) / (white[r] * scale);
  const double new_y_offset = lightness / 116.0;
  const double shift = new_y_offset - f_offset(relative[1]);
  double xyz[3];
  for (int r = 0; r < 3; ++r) xyz[r] = white[r] * scale * t_of_f_offset(r == 1 ? new_y_offset : f_offset(relative[r]) + shift);
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<float>(kXyzToRgb[c][0] * xyz[0] + kXyzToRgb[c][1] * xyz[1] + kXyzToRgb[c][2] * xyz[2]);
}

double lab_lightness(double luminance_cd_m2, double reference_white_cd_m2) {
  return 116.0 * lab_f(luminance_cd_m2 / reference_white_cd_m2) - 16.0;
}

double luminance_of_lab_lightness(double lightness, double reference_white_cd_m2) {
  return reference_white_cd_m2 * lab_f_inverse((lightness + 16.0) / 116.0);
}

LabColour rec709_to_lab(double r, double g, double b, double reference_white_cd_m2) {
  const double x = kRgbToXyz[0][0] * r + kRgbToXyz[0][1] * g + kRgbToXyz[0][2] * b;
  const double y = kRgbToXyz[1][0] * r + kRgbToXyz[1][1] * g + kRgbToXyz[1][2] * b;
  const double z = kRgbToXyz[2][0] * r + kRgbToXyz[2][1] * g + kRgbToXyz[2][2] * b;
  const double scale = reference_white_cd_m2 / kWhiteY;  // Y_n = reference white; X_n, Z_n in proportion
  const double fx = lab_f(x / (kWhiteX * scale)), fy = lab_f(y / (kWhiteY * scale)), fz = lab_f(z / (kWhiteZ * scale));
  return LabColour{116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

void lab_to_rec709(const LabColour& lab, double reference_white_cd_m2, double rgb[3]) {
  const double scale = reference_white_cd_m2 / kWhiteY;
  const double fy = (lab.lightness + 16.0) / 116.0;
  const double fx = fy + lab.a / 500.0, fz = fy - lab.b / 200.0;
  const double x = kWhiteX * scale * lab_f_inverse(fx);
  const double y = kWhiteY * scale * lab_f_inverse(fy);
  const double z = kWhiteZ * scale * lab_f_inverse(fz);
  for (int c = 0; c < 3; ++c) rgb[c] = kXyzToRgb[c][0] * x + kXyzToRgb[c][1] * y + kXyzToRgb[c][2] * z;
}

}  // namespace glarelab
