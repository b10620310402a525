#include "stimuli/display_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace glarelab {

double srgb_encode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

namespace {
// SMPTE ST 2084:2014, 5.3 (also ITU-R BT.2100-2, Table 4): exact binary fractions.
constexpr double kPqM1 = 2610.0 / 16384.0;        // 0.1593017578125
constexpr double kPqM2 = 2523.0 / 4096.0 * 128.0;  // 78.84375
constexpr double kPqC1 = 3424.0 / 4096.0;         // 0.8359375 = c3 - c2 + 1
constexpr double kPqC2 = 2413.0 / 4096.0 * 32.0;   // 18.8515625
constexpr double kPqC3 = 2392.0 / 4096.0 * 32.0;   // 18.6875
}  // namespace

double pq_encode(double luminance_cd_m2) {
  const double y = std::clamp(luminance_cd_m2 / kPqPeakCdM2, 0.0, 1.0);
  const double y_m1 = std::pow(y, kPqM1);
  return std::pow((kPqC1 + kPqC2 * y_m1) / (1.0 + kPqC3 * y_m1), kPqM2);
}

double pq_decode(double signal) {
  const double n_m2 = std::pow(std::clamp(signal, 0.0, 1.0), 1.0 / kPqM2);
  return kPqPeakCdM2 * std::pow(std::max(n_m2 - kPqC1, 0.0) / (kPqC2 - kPqC3 * n_m2), 1.0 / kPqM1);
}

std::array<double, 3> rec709_to_bt2020(const std::array<double, 3>& rec709) {
  static constexpr double kMatrix[3][3] = {{0.6274, 0.3293, 0.0433}, {0.0691, 0.9195, 0.0114}, {0.0164, 0.0880, 0.8956}};
  std::array<double, 3> bt2020{};
  for (std::size_t r = 0; r < 3; ++r)
    bt2020[r] = kMatrix[r][0] * rec709[0] + kMatrix[r][1] * rec709[1] + kMatrix[r][2] * rec709[2];
  return bt2020;
}

double DisplayModel::degrees_for_centred_span(double pixels) const { return centred_span_deg(spec_, pixels); }

double DisplayModel::pixels_for_centred_span(double degrees) const {
  return centred_span_px(spec_, degrees);
}

double DisplayModel::degrees_per_pixel_at_centre() const { return degrees_for_centred_span(1.0); }

double DisplayModel::encode(double luminance_cd_m2) const {
  // An achromatic stimulus has equal channels in any primaries (BT.2087 rows sum to 1).
  return encode_rgb({luminance_cd_m2, luminance_cd_m2, luminance_cd_m2})[1];
}

std::array<double, 3> DisplayModel::encode_rgb(const std::array<double, 3>& rec709_cd_m2) const {
  std::array<double, 3> drive{};
  switch (spec_.encoding) {
    case DisplayEncoding::srgb:
    case DisplayEncoding::gamma:
      for (std::size_t c = 0; c < 3; ++c) {
        const double relative = std::clamp(rec709_cd_m2[c] / spec_.peak_luminance_cd_m2, 0.0, 1.0);
        drive[c] = spec_.encoding == DisplayEncoding::srgb ? srgb_encode(relative) : std::pow(relative, 1.0 / spec_.gamma);
      }
      return drive;
    case DisplayEncoding::pq: {
      const std::array<double, 3> rgb =
          spec_.primaries == DisplayPrimaries::bt2020 ? rec709_to_bt2020(rec709_cd_m2) : rec709_cd_m2;
      for (std::size_t c = 0; c < 3; ++c) drive[c] = pq_encode(std::clamp(rgb[c], 0.0, spec_.peak_luminance_cd_m2));
      return drive;
    }
    case DisplayEncoding::table:
      return spec_.calibration.drive_for_stimulus(rec709_cd_m2);
  }
  return drive;
}

}  // namespace glarelab
