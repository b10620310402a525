#include "stimuli/perception/acuity_loss_float.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/parallel_for.h"
#include "stimuli/float4.h"
#include "stimuli/perception/acuity_loss.h"
#include "stimuli/perception/acuity_marking.h"
#include "stimuli/perception/lab_colour.h"

namespace glarelab {
namespace {

constexpr double kDelta = 6.0 / 29.0;
constexpr double kDeltaCubed = kDelta * kDelta * kDelta;
constexpr double kLinearSlope = 3.0 * kDelta * kDelta;  // t = 3 delta^2 (f - 4/29) on the linear branch
constexpr double kWhite[3] = {kRec709ToXyz[0][0] + kRec709ToXyz[0][1] + kRec709ToXyz[0][2],
                              kRec709ToXyz[1][0] + kRec709ToXyz[1][1] + kRec709ToXyz[1][2],
                              kRec709ToXyz[2][0] + kRec709ToXyz[2][1] + kRec709ToXyz[2][2]};

// Rows are worked in blocks of this many pixels: loops of a fixed count, which the compiler
// vectorises at -O2 (its cheap cost model takes no loop of unknown count); a block is also the unit
// of the passes' bookkeeping (which blocks hold a dark pixel, which need L*).
constexpr int kBlockPx = AcuityMarking::kBlockPx;

// The cube root of t > 0 in float, in operations a compiler can run four at a time: a first guess
// from the bits (a float's bits are a shifted, scaled log2, so dividing them by 3 and adding the
// bits of 1 times 2/3 takes a third of the exponent: within 4 %), then two Halley steps,
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

// The same steps on four values (the same bits as cube_root on each).
Float4 cube_root(Float4 t) {
  Float4 y = t.bits_third_plus(709921077u);
  const Float4 two = Float4::all(2.0f);
  for (int step = 0; step < 2; ++step) {
    const Float4 y3 = y * y * y;
    y = y * (y3 + two * t) / (two * y3 + t);
  }
  return y;
}

constexpr float kLightnessPerT = static_cast<float>(116.0 / kLinearSlope);  // L* = this t on the linear branch

// CIE L* of t = Y / Y_n (lab_lightness), in float: 116 cbrt(t) - 16 above (6/29)^3, else 116 t / (3 delta^2).
float lightness_of(float t) {
  return t > static_cast<float>(kDeltaCubed) ? 116.0f * cube_root(t) - 16.0f : kLightnessPerT * t;
}

// L* of `count` pixels of relative luminance t. In a block, four pixels at a time; four on the
// linear branch (the dark part of a frame) take no cube root, else both branches are computed and
// one kept.
void lightness_block(const float* relative, float* lightness, int count) {
  if (count != kBlockPx) {
    for (int k = 0; k < count; ++k) lightness[k] = lightness_of(relative[k]);
    return;
  }
  const Float4 threshold = Float4::all(static_cast<float>(kDeltaCubed)), per_t = Float4::all(kLightnessPerT);
  for (int q = 0; q < kBlockPx; q += 4) {
    const Float4 t = Float4::load(relative + q);
    const Mask4 cube = t > threshold;
    const Float4 on_line = per_t * t;
    (cube.any() ? select(cube, Float4::all(116.0f) * cube_root(t) - Float4::all(16.0f), on_line) : on_line).store(lightness + q);
  }
}

// Pixels whose L* < 1 (lightness_of(t) < 1 holds only on the linear branch), four at a time.
Mask4 dark4(Float4 t) {
  return (t <= Float4::all(static_cast<float>(kDeltaCubed))) & (Float4::all(kLightnessPerT) * t < Float4::all(1.0f));
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
      capped_below_float_ = 1.0f;
      return;
    }
    for (int step = 0; step < 64 && std::nextafter(lo, hi) < hi; ++step) {
      const double middle = 0.5 * (lo + hi);
      (capped(middle) ? lo : hi) = middle;
    }
    capped_below_ = lo;  // capped at lo, so at every L* below it
    // For a float L*, L* < lo (in double) exactly when L* < the least float >= lo.
    capped_below_float_ = static_cast<float>(lo);
    if (static_cast<double>(capped_below_float_) < lo) capped_below_float_ = std::nextafter(capped_below_float_, INFINITY);
  }
  double operator()(double lightness) const {
    if (!(lightness < 1.0)) return 0.0;
    if (lightness < capped_below_) return settings_.max_sigma_px;
    return acuity_sigma_px(lightness, settings_, pixels_per_degree_);
  }
  // True when every value of the block is either without blur (L* >= 1) or at the cap, so the
  // block takes the cap's kernel alone. Four values at a time, against the cap's float bound.
  bool capped_or_clear(const float* lightness) const {
    const Float4 one = Float4::all(1.0f), cap = Float4::all(capped_below_float_);
    Mask4 other = Mask4::of(false, false, false, false);
    for (int q = 0; q < kBlockPx; q += 4) {
      const Float4 value = Float4::load(lightness + q);
      other = other | ((value < one) & (cap <= value));  // blurred, and not below the cap
    }
    return !other.any();
  }

 private:
  AcuitySettings settings_;
  double pixels_per_degree_;
  double capped_below_ = -INFINITY;
  float capped_below_float_ = -INFINITY;
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

// The pixel rebuilt from its new L*, a* and b* kept (lab_to_rec709 of rec709_to_lab with the new
// L*), in float on a block of pixels at once: with Y's f - 4/29 (on the linear branch, the pixel
// being dark) becoming blurred / 116 (L* = 116 f - 16), X's and Z's f - 4/29 move by as much. The
// linear branch is carried as f - 4/29, which has no cancellation near black (the plain f - 4/29
// would lose 1e-4 of a 0.01 cd/m2 pixel in float); X's and Z's f take a cube root only in a block
// where one of them is off the linear branch (a dark saturated colour).
class PixelRebuild {
 public:
  explicit PixelRebuild(double reference_white_cd_m2) {
    const double scale = reference_white_cd_m2 / kWhite[1];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        to_relative_[r][c] = static_cast<float>(kRec709ToXyz[r][c] / (kWhite[r] * scale));
        from_relative_[c][r] = static_cast<float>(kXyzToRec709[c][r] * kWhite[r] * scale);
      }
  }
  // Four pixels: rgb their channels, blurred their new L*; rgb becomes the rebuilt pixels.
  void four(Float4 (&rgb)[3], Float4 blurred) const {
    const Float4 threshold = Float4::all(static_cast<float>(kDeltaCubed)), per_slope = Float4::all(static_cast<float>(1.0 / kLinearSlope));
    const Float4 four_29 = Float4::all(static_cast<float>(4.0 / 29.0));
    Float4 relative[3], offset[3];
    for (int r = 0; r < 3; ++r)
      relative[r] = Float4::all(to_relative_[r][0]) * rgb[0] + Float4::all(to_relative_[r][1]) * rgb[1] +
                    Float4::all(to_relative_[r][2]) * rgb[2];
    const Float4 new_y = blurred * Float4::all(1.0f / 116.0f);
    const Float4 shift = new_y - relative[1] * per_slope;
    for (int r = 0; r < 3; r += 2) {
      const Mask4 cube = relative[r] > threshold;
      const Float4 on_line = relative[r] * per_slope;
      offset[r] = (cube.any() ? select(cube, cube_root(relative[r]) - four_29, on_line) : on_line) + shift;
    }
    offset[1] = new_y;
    for (int r = 0; r < 3; ++r) {  // the cube only where a lane leaves the linear branch (a dark pixel seldom does)
      const Float4 f = offset[r] + four_29, on_line = Float4::all(static_cast<float>(kLinearSlope)) * offset[r];
      const Mask4 cube = f > Float4::all(static_cast<float>(kDelta));
      relative[r] = cube.any() ? select(cube, f * f * f, on_line) : on_line;
    }
    for (int c = 0; c < 3; ++c)
      rgb[c] = Float4::all(from_relative_[c][0]) * relative[0] + Float4::all(from_relative_[c][1]) * relative[1] +
               Float4::all(from_relative_[c][2]) * relative[2];
  }

 private:
  float to_relative_[3][3];
  float from_relative_[3][3];
};

// What every row chunk shares: the frame, the sigma rule, the cap's kernel in float, the rebuild.
struct AcuityStage {
  ImageRGBA& frame;
  const AcuitySettings& settings;
  AcuityMarking marking;  // Y / Y_n of each pixel and which blocks hold a dark one
  SigmaOfLightness sigma_of;
  int radius;                     // the cap's kernel radius: the largest any pixel takes
  std::vector<float> cap_kernel;  // acuity_kernel(max_sigma_px) in float, 2 radius + 1 weights
  PixelRebuild rebuild;

  // The cap's kernel on a block, out[j] = sum_k w_k taps[k][j] (taps[k]: the block's 16 values
  // moved by k - radius along the pass), in float: positive weights summing to 1 over at most 61
  // values keep the sum within 1e-6 relative.
  void cap_sums(const float* const* taps, float* out) const {
    Float4 s0 = Float4::all(0.0f), s1 = s0, s2 = s0, s3 = s0;  // named: GCC kept an array of them in memory
    for (int k = 0; k <= 2 * radius; ++k) {
      const Float4 w = Float4::all(cap_kernel[static_cast<std::size_t>(k)]);
      const float* tap = taps[k];
      s0 = s0 + w * Float4::load(tap);
      s1 = s1 + w * Float4::load(tap + 4);
      s2 = s2 + w * Float4::load(tap + 8);
      s3 = s3 + w * Float4::load(tap + 12);
    }
    s0.store(out), s1.store(out + 4), s2.store(out + 8), s3.store(out + 12);
  }
};

// One row chunk's passes, made in one sweep down its rows so that each row of the frame is read
// from memory once: at each step the sweep marks the dark blocks of row y + 2 radius, runs the
// horizontal pass on row y + radius (its L* only in the blocks within a kernel of a dark pixel)
// and the vertical pass and rebuild on row y, whose 2 radius + 1 rows of horizontal results are
// kept in a ring. Rows within 2 radius of the chunk's ends are marked and filtered by both chunks
// beside them, each in its own buffers and from a copy of the rows beyond its ends taken before
// any chunk rewrote them, so the result does not depend on the thread count.
class AcuitySweep {
 public:
  // `halo`: the frame's rows [first - 2 radius, first) and [last, last + 2 radius) within the frame,
  // as they were before the stage.
  AcuitySweep(const AcuityStage& stage, int first, int last, const std::vector<float>& halo)
      : s_(stage),
        width_(stage.frame.width_px),
        height_(stage.frame.height_px),
        blocks_((width_ + kBlockPx - 1) / kBlockPx),
        map_first_(std::max(0, first - 2 * stage.radius)),
        first_(first),
        last_(last),
        dark_(static_cast<std::size_t>(std::min(height_, last + 2 * stage.radius) - map_first_) * blocks_, 0),
        near_dark_(dark_.size(), 0),
        near_count_(static_cast<std::size_t>(blocks_), 0),
        ring_(static_cast<std::size_t>(2 * stage.radius + 1) * width_),
        relative_ring_(ring_.size()),
        padded_(static_cast<std::size_t>(width_ + 2 * stage.radius)),
        halo_(halo) {}

  void run() {
    const int r = s_.radius;
    for (int y = map_first_ - 2 * r; y < last_; ++y) {
      if (y + 2 * r >= map_first_ && y + 2 * r < std::min(height_, last_ + 2 * r)) mark_row(y + 2 * r);
      if (y + r >= std::max(0, first_ - r) && y + r < std::min(height_, last_ + r)) first_pass_row(y + r);
      if (y >= first_) second_pass_row(y);
    }
  }

 private:
  std::uint8_t& dark(int y, int b) { return dark_[static_cast<std::size_t>(y - map_first_) * blocks_ + b]; }
  std::uint8_t near_dark(int y, int b) const { return near_dark_[static_cast<std::size_t>(y - map_first_) * blocks_ + b]; }
  float* horizontal_row(int y) { return ring_.data() + static_cast<std::size_t>(y % (2 * s_.radius + 1)) * width_; }
  // Y / Y_n of row y's pixels, found as the row is marked and kept until its vertical pass (rows
  // y to y + 2 radius are held), so the later passes take it without reading the pixels again.
  float* relative_row(int y) { return relative_ring_.data() + static_cast<std::size_t>(y % (2 * s_.radius + 1)) * width_; }
  // Row y of the frame as it was before the stage.
  const float* source_row(int y) const {
    if (y >= first_ && y < last_) return s_.frame.pixel(0, y);
    const int halo_row = y < first_ ? y - map_first_ : (first_ - map_first_) + (y - last_);
    return halo_.data() + 4 * static_cast<std::size_t>(halo_row) * width_;
  }

  void mark_row(int y);
  void first_pass_row(int y);
  void second_pass_row(int y);
  bool second_pass_block(int x0, int y);
  void second_pass_pixel(int x, int y);

  const AcuityStage& s_;
  int width_, height_, blocks_, map_first_, first_, last_;
  std::vector<std::uint8_t> dark_, near_dark_;  // per marked row and block
  std::vector<int> near_count_;                 // per block: marked rows near a dark one within radius of the row
  int counted_through_ = -1;                    // the last row whose near_dark_ is in near_count_
  std::vector<float> ring_, relative_ring_, padded_;
  const float* taps_[2 * 30 + 1] = {};
  KernelCache kernels_;
  const std::vector<float>& halo_;
};

// Which blocks of row y hold a dark pixel, and which lie within a kernel of one along the row.
void AcuitySweep::mark_row(int y) {
  const float* row = source_row(y);
  float* relative = relative_row(y);
  const int reach = (s_.radius + kBlockPx - 1) / kBlockPx;
  for (int b = 0; b < blocks_; ++b) {
    const int x0 = b * kBlockPx;
    const bool any = s_.marking.block(row + 4 * x0, std::min(kBlockPx, width_ - x0), relative + x0);
    dark(y, b) = any ? 1 : 0;
    if (any)
      for (int n = std::max(0, b - reach); n <= std::min(blocks_ - 1, b + reach); ++n)
        near_dark_[static_cast<std::size_t>(y - map_first_) * blocks_ + n] = 1;
  }
}

// L* of the row's needed blocks (those near a dark block within radius rows) into the padded row
// (radius values of the edge pixel on either side, so the kernels need no clamping), then the
// horizontal pass into the ring.
void AcuitySweep::first_pass_row(int y) {
  const int r = s_.radius;
  // The running count of near-dark marks over rows [y - r, y + r].
  for (int add = counted_through_ + 1; add <= std::min(height_ - 1, y + r); ++add)
    if (add >= map_first_)
      for (int b = 0; b < blocks_; ++b) near_count_[static_cast<std::size_t>(b)] += near_dark(add, b);
  counted_through_ = std::max(counted_through_, std::min(height_ - 1, y + r));
  if (y - r - 1 >= map_first_)
    for (int b = 0; b < blocks_; ++b) near_count_[static_cast<std::size_t>(b)] -= near_dark(y - r - 1, b);
  const auto needed = [&](int b) { return near_count_[static_cast<std::size_t>(b)] > 0; };
  float* lightness = padded_.data() + r;
  const float* relative = relative_row(y);
  for (int b = 0; b < blocks_; ++b)
    if (needed(b)) lightness_block(relative + b * kBlockPx, lightness + b * kBlockPx, std::min(kBlockPx, width_ - b * kBlockPx));
  std::fill(padded_.begin(), padded_.begin() + r, lightness[0]);
  std::fill(padded_.end() - r, padded_.end(), lightness[width_ - 1]);
  float* out = horizontal_row(y);
  for (int b = 0; b < blocks_; ++b) {
    if (!needed(b)) continue;
    const int x0 = b * kBlockPx, count = std::min(kBlockPx, width_ - x0);
    std::copy(lightness + x0, lightness + x0 + count, out + x0);
    if (!dark(y, b)) continue;
    if (count == kBlockPx && s_.sigma_of.capped_or_clear(lightness + x0)) {
      float blurred[kBlockPx];
      for (int k = 0; k <= 2 * r; ++k) taps_[k] = lightness + x0 + k - r;
      s_.cap_sums(taps_, blurred);
      for (int q = 0; q < kBlockPx; q += 4) {
        const Float4 before = Float4::load(lightness + x0 + q);
        select(before < Float4::all(1.0f), Float4::load(blurred + q), before).store(out + x0 + q);
      }
      continue;
    }
    for (int x = x0; x < x0 + count; ++x) {  // per-pixel kernels, sums in double
      const double sigma = s_.sigma_of(lightness[x]);
      if (sigma == 0.0) continue;
      const std::vector<double>& kernel = kernels_.of(sigma);
      const int kr = static_cast<int>(kernel.size() / 2);
      double sum = 0.0;
      for (int k = -kr; k <= kr; ++k) sum += kernel[static_cast<std::size_t>(k + kr)] * lightness[x + k];
      out[x] = static_cast<float>(sum);
    }
  }
}

// The vertical pass and the rebuild of one dark pixel with its own kernel, in double.
void AcuitySweep::second_pass_pixel(int x, int y) {
  float* rgb = s_.frame.pixel(x, y);
  const float t = relative_row(y)[x];
  if (!s_.marking.dark(t)) return;
  const float lightness = kLightnessPerT * t;
  const float filtered = horizontal_row(y)[x];
  const bool from_filtered = s_.settings.second_pass == SecondPassSigma::filtered_lightness;
  const double sigma = s_.sigma_of(from_filtered ? filtered : lightness);
  double blurred = filtered;
  if (sigma > 0.0) {
    const std::vector<double>& kernel = kernels_.of(sigma);
    const int kr = static_cast<int>(kernel.size() / 2);
    blurred = 0.0;
    for (int k = -kr; k <= kr; ++k)
      blurred += kernel[static_cast<std::size_t>(k + kr)] * horizontal_row(std::clamp(y + k, 0, height_ - 1))[x];
  }
  if (static_cast<float>(blurred) == lightness) return;  // untouched pixels keep their exact values
  replace_lab_lightness(rgb, blurred, s_.settings.reference_white_cd_m2);  // the same rebuild in double
}

// The vertical pass and the rebuilt pixels of one full block whose dark pixels all take the cap's
// kernel (or none), in float, four pixels at a time; false (nothing done) for any other block.
bool AcuitySweep::second_pass_block(int x0, int y) {
  float* pixels = s_.frame.pixel(x0, y);
  const float* filtered = horizontal_row(y) + x0;
  const float* relative = relative_row(y) + x0;
  const bool from_filtered = s_.settings.second_pass == SecondPassSigma::filtered_lightness;
  Float4 lightness[4];
  Mask4 dark_lanes[4];
  float source[kBlockPx];
  for (int q = 0; q < 4; ++q) {
    const Float4 t = Float4::load(relative + 4 * q);
    dark_lanes[q] = dark4(t);
    lightness[q] = Float4::all(kLightnessPerT) * t;
    // Not dark: L* 1, no blur and no rebuild.
    select(dark_lanes[q], from_filtered ? Float4::load(filtered + 4 * q) : lightness[q], Float4::all(1.0f)).store(source + 4 * q);
  }
  if (!s_.sigma_of.capped_or_clear(source)) return false;
  for (int k = 0; k <= 2 * s_.radius; ++k) taps_[k] = horizontal_row(std::clamp(y + k - s_.radius, 0, height_ - 1)) + x0;
  float vertical[kBlockPx];
  s_.cap_sums(taps_, vertical);
  for (int q = 0; q < 4; ++q) {
    const Float4 blurred = select(Float4::load(source + 4 * q) < Float4::all(1.0f), Float4::load(vertical + 4 * q),
                                  Float4::load(filtered + 4 * q));
    const Mask4 changed = dark_lanes[q] & (blurred != lightness[q]);  // untouched pixels keep their exact values
    if (!changed.any()) continue;
    Float4 rgba[4];
    load_rgba4(pixels + 16 * q, rgba[0], rgba[1], rgba[2], rgba[3]);
    Float4 rgb[3] = {rgba[0], rgba[1], rgba[2]};
    s_.rebuild.four(rgb, blurred);
    if (changed.all())
      store_rgba4(pixels + 16 * q, rgb[0], rgb[1], rgb[2], rgba[3]);
    else
      store_rgba4(pixels + 16 * q, select(changed, rgb[0], rgba[0]), select(changed, rgb[1], rgba[1]),
                  select(changed, rgb[2], rgba[2]), rgba[3]);
  }
  return true;
}

// The row's dark blocks: a block whose dark pixels all take the cap's kernel (or none) in float
// vector form, any other pixel by pixel.
void AcuitySweep::second_pass_row(int y) {
  for (int b = 0; b < blocks_; ++b) {
    if (!dark(y, b)) continue;
    const int x0 = b * kBlockPx, count = std::min(kBlockPx, width_ - x0);
    if (count == kBlockPx && second_pass_block(x0, y)) continue;
    for (int x = x0; x < x0 + count; ++x) second_pass_pixel(x, y);
  }
}

}  // namespace

void apply_acuity_loss_float(ImageRGBA& frame, const AcuitySettings& settings, double pixels_per_degree, int threads,
                             VectorIsa isa) {
  if (frame.empty()) throw std::invalid_argument("perception acuity: the frame is empty");
  validate_acuity_settings(settings);
  if (!std::isfinite(pixels_per_degree) || pixels_per_degree <= 0.0)
    throw std::invalid_argument("perception acuity: pixels per degree must be finite and > 0 (got " +
                                std::to_string(pixels_per_degree) + ")");
  std::vector<float> cap_kernel;
  for (double w : acuity_kernel(settings.max_sigma_px)) cap_kernel.push_back(static_cast<float>(w));
  const AcuityStage stage{frame,
                          settings,
                          AcuityMarking(settings.reference_white_cd_m2, static_cast<float>(kDeltaCubed), kLightnessPerT, isa),
                          SigmaOfLightness(settings, pixels_per_degree),
                          acuity_kernel_radius_px(settings.max_sigma_px),  // no pixel's sigma exceeds the cap
                          std::move(cap_kernel),
                          PixelRebuild(settings.reference_white_cd_m2)};
  // Each chunk's halo copied before any chunk writes (the first call returns when all have).
  const int reach = 2 * stage.radius, height = frame.height_px;
  std::vector<std::vector<float>> halos(static_cast<std::size_t>(std::max(threads, 1)));
  parallel_indexed_chunks(height, threads, [&](int chunk, int first, int last) {
    std::vector<float>& halo = halos[static_cast<std::size_t>(chunk)];
    const auto copy_rows = [&](int from, int to) {
      if (from < to) halo.insert(halo.end(), frame.pixel(0, from), frame.pixel(0, 0) + 4 * static_cast<std::size_t>(to) * frame.width_px);
    };
    copy_rows(std::max(0, first - reach), first);
    copy_rows(last, std::min(height, last + reach));
  });
  parallel_indexed_chunks(height, threads, [&](int chunk, int first, int last) {
    AcuitySweep(stage, first, last, halos[static_cast<std::size_t>(chunk)]).run();
  });
}

}  // namespace glarelab
