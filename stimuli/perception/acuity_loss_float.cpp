#include "stimuli/perception/acuity_loss_float.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "stimuli/perception/acuity_loss.h"
#include "stimuli/perception/lab_colour.h"

namespace glarelab {
namespace {

constexpr double kDelta = 6.0 / 29.0;
constexpr double kDeltaCubed = kDelta * kDelta * kDelta;
constexpr double kLinearSlope = 3.0 * kDelta * kDelta;  // t = 3 delta^2 (f - 4/29) on the linear branch
constexpr double kWhite[3] = {kRec709ToXyz[0][0] + kRec709ToXyz[0][1] + kRec709ToXyz[0][2],
                              kRec709ToXyz[1][0] + kRec709ToXyz[1][1] + kRec709ToXyz[1][2],
                              kRec709ToXyz[2][0] + kRec709ToXyz[2][1] + kRec709ToXyz[2][2]};

// Y / Y_n of a pixel, in float (lab_colour.h: Y_n is the reference white).
struct RelativeLuminance {
  float coefficient[3];
  explicit RelativeLuminance(double reference_white_cd_m2) {
    for (int c = 0; c < 3; ++c)
      coefficient[c] = static_cast<float>(kRec709ToXyz[1][c] / reference_white_cd_m2);
  }
  float of(const float* rgb) const { return coefficient[0] * rgb[0] + coefficient[1] * rgb[1] + coefficient[2] * rgb[2]; }
};

// The cube root of t > 0 in float, in operations a compiler can run four or eight at a time: a first
// guess from the bits (a float's bits are a shifted, scaled log2, so dividing them by 3 and adding
// the bits of 1 times 2/3 takes a third of the exponent: within 4 %), then two Halley steps,
// y <- y (y^3 + 2t) / (2 y^3 + t), each cubing the relative error (4 % -> 6e-5 -> float rounding).
// Agrees with std::cbrt to a few float ulps; tests/perception_float_test.cpp bounds the stage.
float cube_root(float t) {
  std::uint32_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = bits / 3u + 709921077u;
  float y;
  std::memcpy(&y, &bits, sizeof y);
  for (int step = 0; step < 2; ++step) {
    const float y3 = y * y * y;
    y = y * (y3 + 2.0f * t) / (2.0f * y3 + t);
  }
  return y;
}

// CIE L* of t = Y / Y_n (lab_lightness), in float: 116 cbrt(t) - 16 above (6/29)^3, else 116 t / (3 delta^2).
// Both branches are computed and one is kept, so a row's loop has no branch.
float lightness_of(float t) {
  const float cube = 116.0f * cube_root(t) - 16.0f, linear = static_cast<float>(116.0 / kLinearSlope) * t;
  return t > static_cast<float>(kDeltaCubed) ? cube : linear;
}

// Rows are worked in blocks of this many pixels: loops of a fixed count, which the compiler
// vectorises at -O2; the row's last pixels run the same operations one by one.
constexpr int kBlockPx = 16;

// t = Y / Y_n and L* of the pixels [0, count) of rgba into t and lightness.
template <int Count>
void lightness_block(const RelativeLuminance& luminance, const float* rgba, float* t, float* lightness, int count = Count) {
  for (int k = 0; k < (Count > 0 ? Count : count); ++k) t[k] = luminance.of(rgba + 4 * k);
  for (int k = 0; k < (Count > 0 ? Count : count); ++k) lightness[k] = lightness_of(t[k]);
}

// Pixels whose L* < 1: lightness_of(t) < 1 holds only on the linear branch.
bool is_dark(float t) {
  return (t <= static_cast<float>(kDeltaCubed)) & (static_cast<float>(116.0 / kLinearSlope) * t < 1.0f);
}

// acuity_sigma_px, with the cap found once: below `capped_below` sigma is max_sigma_px.
class SigmaOfLightness {
 public:
  SigmaOfLightness(const AcuitySettings& settings, double pixels_per_degree)
      : settings_(settings), pixels_per_degree_(pixels_per_degree) {
    const auto capped = [&](double lightness) {
      return acuity_sigma_px(lightness, settings_, pixels_per_degree_) >= settings_.max_sigma_px;
    };
    if (!capped(0.0)) return;  // the cap never binds (sigma falls with L*, and L* < 0 is L* = 0's)
    double lo = 0.0, hi = 1.0;
    if (capped(std::nextafter(1.0, 0.0))) {
      capped_below_ = 1.0;
      return;
    }
    for (int step = 0; step < 64 && std::nextafter(lo, hi) < hi; ++step) {
      const double middle = 0.5 * (lo + hi);
      (capped(middle) ? lo : hi) = middle;
    }
    capped_below_ = lo;  // capped at lo, so at every L* below it
  }
  double operator()(double lightness) const {
    if (!(lightness < 1.0)) return 0.0;
    if (lightness < capped_below_) return settings_.max_sigma_px;
    return acuity_sigma_px(lightness, settings_, pixels_per_degree_);
  }

 private:
  AcuitySettings settings_;
  double pixels_per_degree_;
  double capped_below_ = -INFINITY;
};

// acuity_kernel of the last sigma asked for (neighbouring pixels mostly share one: the cap).
class KernelCache {
 public:
  const std::vector<double>& of(double sigma_px) {
    if (sigma_px != sigma_px_) {
      weights_ = acuity_kernel(sigma_px);
      sigma_px_ = sigma_px;
    }
    return weights_;
  }

 private:
  double sigma_px_ = -1.0;
  std::vector<double> weights_;
};

// f - 4/29 of t on CIE's f (lab_colour.h), without cancellation on the linear branch.
double f_offset(double t) { return t > kDeltaCubed ? std::cbrt(t) - 4.0 / 29.0 : t / kLinearSlope; }
// t of f - 4/29.
double t_of_f_offset(double g) {
  const double f = g + 4.0 / 29.0;
  return f > kDelta ? f * f * f : kLinearSlope * g;
}

// The dark pixel rgb with L* moved to `blurred`, a* and b* kept (lab_to_rec709 of rec709_to_lab with
// the new L*): Y's f - 4/29 becomes blurred / 116 (L* = 116 f - 16), X's and Z's move by as much.
void rebuild_pixel(float* rgb, double blurred, double reference_white_cd_m2) {
  const double scale = reference_white_cd_m2 / kWhite[1];
  double relative[3];
  for (int r = 0; r < 3; ++r)
    relative[r] = (kRec709ToXyz[r][0] * rgb[0] + kRec709ToXyz[r][1] * rgb[1] + kRec709ToXyz[r][2] * rgb[2]) /
                  (kWhite[r] * scale);
  const double new_y_offset = blurred / 116.0;
  const double shift = new_y_offset - f_offset(relative[1]);
  double xyz[3];
  for (int r = 0; r < 3; ++r)
    xyz[r] = kWhite[r] * scale * t_of_f_offset(r == 1 ? new_y_offset : f_offset(relative[r]) + shift);
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<float>(kXyzToRec709[c][0] * xyz[0] + kXyzToRec709[c][1] * xyz[1] + kXyzToRec709[c][2] * xyz[2]);
}

std::size_t at(int x, int y, int width) { return static_cast<std::size_t>(y) * width + x; }

}  // namespace

void apply_acuity_loss_float(ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree, int threads) {
  if (frame.empty()) throw std::invalid_argument("perception acuity: the frame is empty");
  validate_acuity_settings(settings);
  if (!std::isfinite(pixels_per_degree) || pixels_per_degree <= 0.0)
    throw std::invalid_argument("perception acuity: pixels per degree must be finite and > 0 (got " +
                                std::to_string(pixels_per_degree) + ")");
  const int width = frame.width_px, height = frame.height_px;
  const RelativeLuminance luminance(settings.reference_white_cd_m2);
  const SigmaOfLightness sigma_of(settings, pixels_per_degree);
  std::vector<float> horizontal(static_cast<std::size_t>(width) * height);
  // Pass 1: L* and the horizontal pass, row by row.
  parallel_chunks(height, threads, [&](int first, int last) {
    std::vector<float> lightness(static_cast<std::size_t>(width));
    KernelCache kernels;
    for (int y = first; y < last; ++y) {
      const float* row = frame.pixel(0, y);
      float t[kBlockPx];
      int block = 0;
      for (; block + kBlockPx <= width; block += kBlockPx)
        lightness_block<kBlockPx>(luminance, row + 4 * block, t, lightness.data() + block);
      lightness_block<0>(luminance, row + 4 * block, t, lightness.data() + block, width - block);
      const bool any_dark = std::any_of(lightness.begin(), lightness.end(), [](float value) { return value < 1.0f; });
      float* out = &horizontal[at(0, y, width)];
      std::copy(lightness.begin(), lightness.end(), out);
      if (!any_dark) continue;
      for (int x = 0; x < width; ++x) {
        const double sigma = sigma_of(lightness[static_cast<std::size_t>(x)]);
        if (sigma == 0.0) continue;
        const std::vector<double>& kernel = kernels.of(sigma);
        const int radius = static_cast<int>(kernel.size() / 2);
        double sum = 0.0;
        for (int k = -radius; k <= radius; ++k)
          sum += kernel[static_cast<std::size_t>(k + radius)] *
                 lightness[static_cast<std::size_t>(std::clamp(x + k, 0, width - 1))];
        out[x] = static_cast<float>(sum);
      }
    }
  });
  // Pass 2: the vertical pass and the rebuilt pixels, only where L* < 1.
  const bool second_from_filtered = settings.second_pass == SecondPassSigma::filtered_lightness;
  parallel_chunks(height, threads, [&](int first, int last) {
    KernelCache kernels;
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width; ++x) {
        // A block without a dark pixel is passed over after one vectorised look.
        if (x % kBlockPx == 0 && x + kBlockPx <= width) {
          int dark = 0;
          for (int k = 0; k < kBlockPx; ++k) dark += is_dark(luminance.of(frame.pixel(x + k, y))) ? 1 : 0;
          if (dark == 0) {
            x += kBlockPx - 1;
            continue;
          }
        }
        float* rgb = frame.pixel(x, y);
        const float t = luminance.of(rgb);
        if (!is_dark(t)) continue;
        const float lightness = lightness_of(t);
        const float filtered = horizontal[at(x, y, width)];
        const double sigma = sigma_of(second_from_filtered ? filtered : lightness);
        double blurred = filtered;
        if (sigma > 0.0) {
          const std::vector<double>& kernel = kernels.of(sigma);
          const int radius = static_cast<int>(kernel.size() / 2);
          blurred = 0.0;
          for (int k = -radius; k <= radius; ++k)
            blurred += kernel[static_cast<std::size_t>(k + radius)] * horizontal[at(x, std::clamp(y + k, 0, height - 1), width)];
        }
        if (static_cast<float>(blurred) == lightness) continue;  // untouched pixels keep their exact values
        rebuild_pixel(rgb, blurred, settings.reference_white_cd_m2);
      }
  });
}

}  // namespace glarelab
