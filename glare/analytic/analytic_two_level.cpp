#include "glare/analytic/analytic_two_level.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/parallel_for.h"

namespace glarelab {

void check_two_level_split(const TwoLevelSplit& split) {
  if (split.near_inner_px < 0 || split.near_outer_px <= split.near_inner_px)
    throw std::invalid_argument("glare/analytic/analytic_two_level: the near radii must satisfy 0 <= inner < outer, got " +
                                std::to_string(split.near_inner_px) + " and " + std::to_string(split.near_outer_px));
  if (split.factor != 2 && split.factor != 4)
    throw std::invalid_argument("glare/analytic/analytic_two_level: the far decimation factor must be 2 or 4, got " +
                                std::to_string(split.factor));
}

double near_weight(const TwoLevelSplit& split, double r_px) {
  if (r_px <= split.near_inner_px) return 1.0;
  if (r_px >= split.near_outer_px) return 0.0;
  // Raised cosine: continuous with a continuous slope at both ends, so K_far has no edge for the
  // coarse level to alias.
  const double t = (r_px - split.near_inner_px) / static_cast<double>(split.near_outer_px - split.near_inner_px);
  return 0.5 * (1.0 + std::cos(std::numbers::pi * t));
}

DisplayKernel near_kernel(const DisplayKernel& kernel, const TwoLevelSplit& split) {
  check_two_level_split(split);
  DisplayKernel near;
  near.half_width_px = std::min(split.near_outer_px, kernel.half_width_px);
  near.half_height_px = std::min(split.near_outer_px, kernel.half_height_px);
  near.channels = kernel.channels;
  near.values.assign(static_cast<std::size_t>(near.channels) * near.width_px() * near.height_px(), 0.0);
  for (int c = 0; c < near.channels; ++c)
    for (int dy = -near.half_height_px; dy <= near.half_height_px; ++dy)
      for (int dx = -near.half_width_px; dx <= near.half_width_px; ++dx)
        near.at(c, dx, dy) = near_weight(split, std::hypot(dx, dy)) * kernel.at(c, dx, dy);
  return near;
}

DisplayKernel coarse_far_kernel(const DisplayKernel& kernel, const TwoLevelSplit& split, int coarse_half_width_px,
                                int coarse_half_height_px) {
  check_two_level_split(split);
  const int f = split.factor;
  DisplayKernel coarse;
  coarse.half_width_px = coarse_half_width_px;
  coarse.half_height_px = coarse_half_height_px;
  coarse.channels = kernel.channels;
  coarse.values.assign(static_cast<std::size_t>(coarse.channels) * coarse.width_px() * coarse.height_px(), 0.0);
  // t(d) per axis: (f - |d|) / f, the overlap of a source block and a target block d pixels apart.
  std::vector<double> tent(static_cast<std::size_t>(2 * f - 1));
  for (int d = -(f - 1); d <= f - 1; ++d) tent[static_cast<std::size_t>(d + f - 1)] = (f - std::abs(d)) / static_cast<double>(f);
  parallel_chunks(coarse.height_px(), kGlareCpuThreads, [&](int first, int last) {
    for (int row = first; row < last; ++row) {
      const int cy = row - coarse_half_height_px;
      for (int cx = -coarse_half_width_px; cx <= coarse_half_width_px; ++cx)
        for (int c = 0; c < coarse.channels; ++c) {
          double sum = 0.0;
          for (int ey = -(f - 1); ey <= f - 1; ++ey) {
            const int dy = f * cy + ey;
            if (std::abs(dy) > kernel.half_height_px) continue;
            for (int ex = -(f - 1); ex <= f - 1; ++ex) {
              const int dx = f * cx + ex;
              if (std::abs(dx) > kernel.half_width_px) continue;
              // Beyond the outer radius on either axis the near weight is 0: no square root.
              const bool outside = std::abs(dx) >= split.near_outer_px || std::abs(dy) >= split.near_outer_px;
              const double w = outside ? 0.0 : near_weight(split, std::hypot(dx, dy));
              const double far = (1.0 - w) * kernel.at(c, dx, dy);
              sum += tent[static_cast<std::size_t>(ex + f - 1)] * tent[static_cast<std::size_t>(ey + f - 1)] * far;
            }
          }
          coarse.at(c, cx, cy) = sum;
        }
    }
  });
  return coarse;
}

TwoLevelConvolution::TwoLevelConvolution(int width_px, int height_px, const TwoLevelSplit& split, int threads)
    : width_(width_px),
      height_(height_px),
      threads_(std::max(1, threads)),
      split_(split),
      near_half_width_(std::min(split.near_outer_px, std::max(0, width_px - 1))),
      near_half_height_(std::min(split.near_outer_px, std::max(0, height_px - 1))),
      near_((check_two_level_split(split), width_px), height_px, near_half_width_, near_half_height_, threads) {
  // The far part vanishes when the whole kernel (every offset within the frame) lies inside the
  // inner radius.
  far_level_ = std::hypot(width_px - 1, height_px - 1) > split.near_inner_px;
  if (!far_level_) return;
  coarse_width_ = (width_px + split.factor - 1) / split.factor;
  coarse_height_ = (height_px + split.factor - 1) / split.factor;
  far_ = std::make_unique<DisplayKernelConvolution>(coarse_width_ + 2, coarse_height_ + 2, coarse_width_ + 1,
                                                    coarse_height_ + 1, threads_);
  coarse_in_ = ImageRGBA(coarse_width_ + 2, coarse_height_ + 2);
  for (std::size_t i = 3; i < coarse_in_.rgba.size(); i += 4) coarse_in_.rgba[i] = 1.0f;
}

std::size_t TwoLevelConvolution::spectrum_bytes() const {
  return near_.spectrum_bytes() + (far_ ? far_->spectrum_bytes() : 0);
}

void TwoLevelConvolution::set_components(const std::vector<DisplayKernel>& components) {
  std::vector<DisplayKernel> near, far;
  for (const DisplayKernel& kernel : components) {
    if (kernel.half_width_px != width_ - 1 || kernel.half_height_px != height_ - 1)
      throw std::invalid_argument("glare/analytic/analytic_two_level: a kernel is not of the frame's whole-display size");
    near.push_back(near_kernel(kernel, split_));
    if (far_level_) far.push_back(coarse_far_kernel(kernel, split_, coarse_width_ + 1, coarse_height_ + 1));
  }
  near_.set_components(near);
  if (far_level_) far_->set_components(far);
}

void TwoLevelConvolution::set_weights(const std::vector<double>& weights) {
  near_.set_weights(weights);
  if (far_level_) far_->set_weights(weights);
}

void TwoLevelConvolution::convolve(const ImageRGBA& source, ImageRGBA& out) {
  // The near level checks the frame (size, NaN, Inf, negative values) before anything is written.
  near_.convolve(source, out);
  if (!far_level_) return;
  const int f = split_.factor;
  const float block_area = static_cast<float>(f * f);
  // Area average of each block into the coarse frame, one block of margin on every side (zero:
  // nothing shines from beyond the display; partial blocks at the edge are averaged over the
  // whole block, so the coarse frame holds the frame's sum / f^2).
  parallel_chunks(coarse_height_, threads_, [&](int first, int last) {
    for (int by = first; by < last; ++by)
      for (int bx = 0; bx < coarse_width_; ++bx) {
        float sum[3] = {0.0f, 0.0f, 0.0f};
        for (int y = by * f; y < std::min(height_, (by + 1) * f); ++y)
          for (int x = bx * f; x < std::min(width_, (bx + 1) * f); ++x) {
            const float* p = source.pixel(x, y);
            for (int c = 0; c < 3; ++c) sum[c] += p[c];
          }
        float* target = coarse_in_.pixel(bx + 1, by + 1);
        for (int c = 0; c < 3; ++c) target[c] = sum[c] / block_area;
      }
  });
  far_->convolve(coarse_in_, coarse_out_);
  // Bilinear interpolation at the fine pixel centres: pixel x sits at coarse coordinate
  // (x + 0.5) / f - 0.5 (block X's centre at X), that is at (x + 0.5) / f + 0.5 in the padded
  // coarse frame.
  std::vector<int> column(static_cast<std::size_t>(width_));
  std::vector<float> column_weight(static_cast<std::size_t>(width_));
  for (int x = 0; x < width_; ++x) {
    const double u = (x + 0.5) / f + 0.5;
    column[static_cast<std::size_t>(x)] = static_cast<int>(std::floor(u));
    column_weight[static_cast<std::size_t>(x)] = static_cast<float>(u - std::floor(u));
  }
  parallel_chunks(height_, threads_, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const double v = (y + 0.5) / f + 0.5;
      const int row = static_cast<int>(std::floor(v));
      const float b = static_cast<float>(v - row);
      const float* top = coarse_out_.pixel(0, row);
      const float* bottom = coarse_out_.pixel(0, row + 1);
      float* target = out.pixel(0, y);
      for (int x = 0; x < width_; ++x) {
        const int i = column[static_cast<std::size_t>(x)];
        const float a = column_weight[static_cast<std::size_t>(x)];
        for (int c = 0; c < 3; ++c) {
          const float upper = top[4 * i + c] + a * (top[4 * (i + 1) + c] - top[4 * i + c]);
          const float lower = bottom[4 * i + c] + a * (bottom[4 * (i + 1) + c] - bottom[4 * i + c]);
          target[4 * x + c] += upper + b * (lower - upper);
        }
      }
    }
  });
}

}  // namespace glarelab
