// Writes the demo's HDR scenes (examples/scenes/lamp_*.exr): a dim room with one round lamp of a
// given luminance. Run by `make demo_scenes` (scripts/CMakeLists.txt); the results are committed
// so the demo needs nothing but a clone.
//   usage: make_demo_scenes OUTPUT_DIR
#include <cmath>
#include <cstdio>
#include <string>

#include "core/exr_io.h"

namespace {

// 256 x 256 pixels: background rising gently from 0.5 to 2 cd/m2 towards the floor (a lit room at
// mesopic level), a lamp disc of radius 10 px with an anti-aliased edge (area coverage from a 4x4
// subpixel grid), luminance `lamp_cd_m2`, neutral (D65) colour.
glarelab::ImageRGBA lamp_scene(double lamp_cd_m2) {
  constexpr int kSize = 256;
  constexpr double kRadiusPx = 10.0;
  constexpr double kCentre = kSize / 2.0;
  glarelab::ImageRGBA image(kSize, kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      int covered = 0;
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx) {
          const double dx = x + (sx + 0.5) / 4.0 - kCentre;
          const double dy = y + (sy + 0.5) / 4.0 - kCentre;
          covered += (dx * dx + dy * dy <= kRadiusPx * kRadiusPx) ? 1 : 0;
        }
      const double coverage = covered / 16.0;
      const double background = 0.5 + 1.5 * y / (kSize - 1.0);
      const auto value = static_cast<float>(coverage * lamp_cd_m2 + (1.0 - coverage) * background);
      float* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = value;
      p[3] = 1.0f;
    }
  }
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  for (int lamp : {100, 105, 115, 130, 160, 200}) {
    const std::string path = dir + "/lamp_" + std::to_string(lamp) + ".exr";
    glarelab::ExrWriteOptions options;
    options.pixel_type = glarelab::ExrPixelType::half;  // 100..200 cd/m2 are exact in half
    options.write_alpha = false;
    glarelab::write_exr(path, lamp_scene(lamp), options);
    std::printf("wrote %s\n", path.c_str());
  }
  return 0;
}
