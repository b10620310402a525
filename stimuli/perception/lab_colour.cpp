#include "stimuli/perception/lab_colour.h"

#include <cmath>

namespace glarelab {
namespace {

// Linear Rec.709 (D65) to CIE XYZ and back, from the primaries and white of IEC 61966-2-1.
constexpr double kRgbToXyz[3][3] = {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
                                    {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
                                    {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}};
constexpr double kXyzToRgb[3][3] = {{3.24096994190452134, -1.53738317757009346, -0.49861076029300328},
                                    {-0.96924363628087983, 1.87596750150772067, 0.04155505740717561},
                                    {0.05563007969699361, -0.20397695888897657, 1.05697151424287856}};
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

}  // namespace

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
