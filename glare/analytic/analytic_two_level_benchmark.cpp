#include "core/clock.h"
#include "glare/analytic/analytic_two_level_benchmark.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>

#include "glare/analytic/analytic_glare.h"
#include "glare/analytic/display_kernel_convolution.h"
#include "glare/cpu/fftw_floor.h"

namespace glarelab {
namespace {

double frame_s(AnalyticGlare& glare, const ImageRGBA& frame, ImageRGBA& out) {
  const auto start = std::chrono::steady_clock::now();
  glare.convolve(frame, out);
  return seconds_since(start);
}

}  // namespace

ImageRGBA analytic_benchmark_frame(int width, int height) {
  ImageRGBA frame(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = frame.pixel(x, y);
      const float base = 0.5f + 1.5f * static_cast<float>(x) / static_cast<float>(width);
      p[0] = base, p[1] = 0.9f * base, p[2] = 0.7f * base, p[3] = 1.0f;
    }
  const double lamps[5][3] = {{0.2, 0.3, 2e3}, {0.45, 0.5, 2e4}, {0.7, 0.25, 5e3}, {0.85, 0.7, 1e4}, {0.3, 0.8, 3e3}};
  for (const auto& lamp : lamps) {
    const int cx = static_cast<int>(lamp[0] * width), cy = static_cast<int>(lamp[1] * height);
    for (int y = std::max(0, cy - 3); y <= std::min(height - 1, cy + 3); ++y)
      for (int x = std::max(0, cx - 3); x <= std::min(width - 1, cx + 3); ++x)
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= 9)
          for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = static_cast<float>(lamp[2]);
  }
  for (int y = height / 10; y < height / 5; ++y)
    for (int x = width / 20; x < width / 8; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 400.0f;
  return frame;
}

std::vector<bool> near_bright_pixels(const ImageRGBA& frame, float threshold, int radius_px) {
  const int w = frame.width_px, h = frame.height_px;
  std::vector<int> rows(static_cast<std::size_t>(w) * h, 0);
  // Separable dilation by a square: along rows, then along columns.
  for (int y = 0; y < h; ++y) {
    int last = -1000000000;
    std::vector<int> from_left(static_cast<std::size_t>(w)), from_right(static_cast<std::size_t>(w));
    for (int x = 0; x < w; ++x) {
      const float* p = frame.pixel(x, y);
      if (std::max({p[0], p[1], p[2]}) > threshold) last = x;
      from_left[static_cast<std::size_t>(x)] = x - last;
    }
    last = 2000000000;
    for (int x = w - 1; x >= 0; --x) {
      const float* p = frame.pixel(x, y);
      if (std::max({p[0], p[1], p[2]}) > threshold) last = x;
      from_right[static_cast<std::size_t>(x)] = last - x;
    }
    for (int x = 0; x < w; ++x)
      rows[static_cast<std::size_t>(y) * w + x] =
          std::min(from_left[static_cast<std::size_t>(x)], from_right[static_cast<std::size_t>(x)]) <= radius_px;
  }
  std::vector<bool> near(rows.size(), false);
  for (int x = 0; x < w; ++x) {
    int last = -1000000000;
    for (int y = 0; y < h; ++y) {
      if (rows[static_cast<std::size_t>(y) * w + x]) last = y;
      if (y - last <= radius_px) near[static_cast<std::size_t>(y) * w + x] = true;
    }
    last = 2000000000;
    for (int y = h - 1; y >= 0; --y) {
      if (rows[static_cast<std::size_t>(y) * w + x]) last = y;
      if (last - y <= radius_px) near[static_cast<std::size_t>(y) * w + x] = true;
    }
  }
  return near;
}

FrameErrors frame_errors(const ImageRGBA& fast, const ImageRGBA& exact, const std::vector<bool>& near) {
  double peak = 0.0, diff2 = 0.0, ref2 = 0.0, worst = 0.0, worst_near = 0.0, worst_far = 0.0, far_relative = 0.0;
  for (std::size_t i = 0; i < exact.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) {
      const double e = exact.rgba[i + c], d = std::abs(static_cast<double>(fast.rgba[i + c]) - e);
      peak = std::max(peak, std::abs(e));
      worst = std::max(worst, d);
      diff2 += d * d;
      ref2 += e * e;
      if (near[i / 4]) {
        worst_near = std::max(worst_near, d);
      } else {
        worst_far = std::max(worst_far, d);
        if (e != 0.0) far_relative = std::max(far_relative, d / std::abs(e));
      }
    }
  FrameErrors errors;
  if (peak > 0.0) {
    errors.max = worst / peak;
    errors.near_max = worst_near / peak;
    errors.far_max = worst_far / peak;
  }
  errors.l2 = ref2 > 0.0 ? std::sqrt(diff2 / ref2) : 0.0;
  errors.far_relative = far_relative;
  return errors;
}

TwoLevelBenchmarkResult run_two_level_benchmark(const TwoLevelBenchmarkOptions& options) {
  check_two_level_split(options.split);
  TwoLevelBenchmarkResult result;
  result.width_px = options.width_px;
  result.height_px = options.height_px;
  result.threads = kGlareCpuThreads;
  result.split = options.split;
  auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const DisplayGeometry geometry{options.viewing_distance_mm, options.pixel_pitch_mm};
  const ImageRGBA frame = analytic_benchmark_frame(options.width_px, options.height_px);
  const double deg_per_px = std::atan(options.pixel_pitch_mm / options.viewing_distance_mm) * 180.0 / std::numbers::pi;
  const std::vector<bool> near =
      near_bright_pixels(frame, 100.0f, static_cast<int>(std::ceil(options.near_sources_deg / deg_per_px)));
  struct Case {
    std::string label;
    GlareModel model;
    SpencerRegime regime;
  };
  const Case cases[] = {{"spencer mesopic", GlareModel::spencer, SpencerRegime::mesopic},
                        {"spencer adaptive (at 1 cd/m2)", GlareModel::spencer, SpencerRegime::adaptive},
                        {"cie", GlareModel::cie, SpencerRegime::photopic}};
  for (const Case& c : cases) {
    TwoLevelBenchmarkRow row;
    row.model = c.label;
    AnalyticGlareOptions glare_options;
    glare_options.model = c.model;
    glare_options.regime = c.regime;
    glare_options.geometry = geometry;
    glare_options.width_px = options.width_px;
    glare_options.height_px = options.height_px;
    glare_options.split = options.split;
    glare_options.keep_repeated_frame = false;  // every run a convolution
    ImageRGBA full_out, two_level_out;
    say("analytic glare: " + c.label + ", integrating the kernels");
    glare_options.convolution = AnalyticConvolution::full;
    AnalyticGlare full(glare_options);
    full.adapt(1.0);
    const spencer::Mixture mixture = full.mixture();
    row.full_fft_cols = full.fft_cols();
    row.full_fft_rows = full.fft_rows();
    row.full_memory_mib = static_cast<double>(full.memory_bytes()) / (1024.0 * 1024.0);
    glare_options.convolution = AnalyticConvolution::two_level;
    AnalyticGlare two_level(glare_options);
    two_level.adapt(1.0);
    row.two_level_memory_mib = static_cast<double>(two_level.memory_bytes()) / (1024.0 * 1024.0);
    row.near_fft_cols = two_level.two_level()->near_fft_cols();
    row.near_fft_rows = two_level.two_level()->near_fft_rows();
    row.far_fft_cols = two_level.two_level()->far_fft_cols();
    row.far_fft_rows = two_level.two_level()->far_fft_rows();
    FftwRgbConvolutionFloor floor(row.full_fft_rows, row.full_fft_cols);
    // Interleaved, the fastest of each kept: a load that comes and goes then weighs on all three
    // alike, and the ratios to the floor hold.
    say("analytic glare: " + c.label + ", timing the floor, the full and the two-level frames");
    row.floor_s = row.full_frame_s = row.two_level_frame_s = 1e300;
    for (int k = 0; k < std::max(1, options.frames); ++k) {
      row.floor_s = std::min(row.floor_s, floor.run_s());
      row.full_frame_s = std::min(row.full_frame_s, frame_s(full, frame, full_out));
      row.two_level_frame_s = std::min(row.two_level_frame_s, frame_s(two_level, frame, two_level_out));
    }
    say("analytic glare: " + c.label + ", float64 reference");
    const AnalyticPsf psf = c.model == GlareModel::cie ? AnalyticPsf::cie(ObserverEye{}) : AnalyticPsf::spencer(mixture);
    const DisplayKernel kernel =
        analytic_display_kernel(psf, geometry, options.width_px - 1, options.height_px - 1, kGlareCpuThreads);
    const ImageRGBA exact = convolve_with_kernel_float64(frame, kernel);
    row.full = frame_errors(full_out, exact, near);
    row.two_level = frame_errors(two_level_out, exact, near);
    result.rows.push_back(row);
  }
  return result;
}

std::string format_two_level_benchmark(const TwoLevelBenchmarkResult& result) {
  std::ostringstream out;
  out.precision(3);
  out << "Analytic glare, full against two-level: a " << result.width_px << " x " << result.height_px
      << " HDR frame (a dim room with lamps of 2e3-2e4 cd/m2 and a 400 cd/m2 window), " << result.threads
      << " threads. Full: FFT of twice the frame, beside the FFTW floor of its size (3 forward + 3 inverse real "
         "transforms) in the same run. Two-level: the kernel inside "
      << result.split.near_inner_px << " px (cross-fade to " << result.split.near_outer_px
      << " px) at full resolution, the rest at 1/" << result.split.factor
      << " resolution, bilinear back. Errors against the float64 full convolution: max |error| / peak, L2, max / "
         "peak near the bright sources and away from them, and max |error| / local value away from them.\n\n"
      << "| model | path | FFT | frame ms | floor ms | frame / floor | max / peak | L2 | near max | far max | far "
         "relative | spectra MiB |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const TwoLevelBenchmarkRow& r : result.rows) {
    out << "| " << r.model << " | full | " << r.full_fft_cols << " x " << r.full_fft_rows << " | "
        << 1e3 * r.full_frame_s << " | " << 1e3 * r.floor_s << " | " << r.full_frame_s / r.floor_s << " | "
        << r.full.max << " | " << r.full.l2 << " | " << r.full.near_max << " | " << r.full.far_max << " | "
        << r.full.far_relative << " | " << r.full_memory_mib << " |\n";
    out << "| " << r.model << " | two-level | " << r.near_fft_cols << " x " << r.near_fft_rows << " + "
        << r.far_fft_cols << " x " << r.far_fft_rows << " | " << 1e3 * r.two_level_frame_s << " | "
        << 1e3 * r.floor_s << " | " << r.two_level_frame_s / r.floor_s << " | " << r.two_level.max << " | "
        << r.two_level.l2 << " | " << r.two_level.near_max << " | " << r.two_level.far_max << " | "
        << r.two_level.far_relative << " | " << r.two_level_memory_mib << " |\n";
  }
  return out.str();
}

}  // namespace glarelab
