// Compares the frames two runs saved (`run --save-frames DIR`): every EXR in BEFORE_DIR against the
// file of the same name in AFTER_DIR. For refactors that must not change what a participant sees
// (scripts/compare_runs.sh): a frame is "identical" when every channel value is the same bits,
// "within 1e-6" when the values differ only as a changed order of floating-point sums can make
// them differ (every |a - b| at most 1e-6 of max(|a|, |b|), or of the frame's peak where the pixel
// is darker than a millionth of it: a sum's rounding is relative to its largest terms, which can
// be the peak's light spread into a dark pixel), else "DIFFERENT" with where and by how much.
//   compare_frames BEFORE_DIR AFTER_DIR
// Prints one line per frame; exit 0 when none is DIFFERENT and both folders hold the same names,
// 1 otherwise, 2 for unreadable input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include "core/exr_io.h"

namespace fs = std::filesystem;

namespace {

constexpr double kRelativeTolerance = 1e-6;

std::set<std::string> exr_names(const fs::path& folder) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && entry.path().extension() == ".exr") names.insert(entry.path().filename().string());
  return names;
}

struct FrameDifference {
  bool same_size = true;
  bool identical = true;
  double worst_ratio = 0.0;  // max |a - b| / allowed difference's scale (1e-6 of it passes)
  int worst_x = 0, worst_y = 0, worst_channel = 0;
  float worst_before = 0.0f, worst_after = 0.0f;
};

FrameDifference compare(const glarelab::ImageRGBA& before, const glarelab::ImageRGBA& after) {
  FrameDifference d;
  if (before.width_px != after.width_px || before.height_px != after.height_px) {
    d.same_size = false;
    d.identical = false;
    return d;
  }
  double peak = 0.0;
  for (float v : before.rgba) peak = std::max(peak, std::fabs(static_cast<double>(v)));
  for (float v : after.rgba) peak = std::max(peak, std::fabs(static_cast<double>(v)));
  const double dark_floor = peak * 1e-6;
  for (std::size_t i = 0; i < before.rgba.size(); ++i) {
    const float a = before.rgba[i], b = after.rgba[i];
    if (a == b || (std::isnan(a) && std::isnan(b))) continue;
    d.identical = false;
    const double scale = std::max({std::fabs(static_cast<double>(a)), std::fabs(static_cast<double>(b)), dark_floor});
    const double ratio = scale > 0.0 ? std::fabs(static_cast<double>(a) - b) / scale : INFINITY;
    if (!(ratio <= d.worst_ratio)) {
      d.worst_ratio = std::isnan(ratio) ? INFINITY : ratio;
      const std::size_t pixel = i / 4;
      d.worst_x = static_cast<int>(pixel % static_cast<std::size_t>(before.width_px));
      d.worst_y = static_cast<int>(pixel / static_cast<std::size_t>(before.width_px));
      d.worst_channel = static_cast<int>(i % 4);
      d.worst_before = a;
      d.worst_after = b;
    }
  }
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: compare_frames BEFORE_DIR AFTER_DIR\n");
    return 2;
  }
  const fs::path before_dir = argv[1], after_dir = argv[2];
  int status = 0;
  try {
    const std::set<std::string> before = exr_names(before_dir), after = exr_names(after_dir);
    for (const std::string& name : before)
      if (!after.contains(name)) std::printf("%s: missing after\n", name.c_str()), status = 1;
    for (const std::string& name : after)
      if (!before.contains(name)) std::printf("%s: new after\n", name.c_str()), status = 1;
    int identical = 0, close = 0;
    for (const std::string& name : before) {
      if (!after.contains(name)) continue;
      const FrameDifference d = compare(glarelab::read_exr((before_dir / name).string()).image,
                                        glarelab::read_exr((after_dir / name).string()).image);
      if (d.identical) {
        ++identical;
      } else if (d.same_size && d.worst_ratio <= kRelativeTolerance) {
        ++close;
        std::printf("%s: within 1e-6 (largest relative difference %.3g)\n", name.c_str(), d.worst_ratio);
      } else if (!d.same_size) {
        std::printf("%s: DIFFERENT sizes\n", name.c_str());
        status = 1;
      } else {
        std::printf("%s: DIFFERENT: relative %.3g at pixel (%d, %d) channel %d: %.9g before, %.9g after\n", name.c_str(),
                    d.worst_ratio, d.worst_x, d.worst_y, d.worst_channel, static_cast<double>(d.worst_before),
                    static_cast<double>(d.worst_after));
        status = 1;
      }
    }
    std::printf("frames: %d identical, %d within 1e-6, %zu compared\n", identical, close, before.size());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "compare_frames: %s\n", error.what());
    return 2;
  }
  return status;
}
