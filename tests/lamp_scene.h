#pragma once
// A 32 x 32 black scene with a 4 x 4 lamp in the middle, for tests of what render and run show.
#include <string>

#include "core/exr_io.h"
#include "core/image.h"

namespace glarelab::test {

inline void write_lamp_scene(const std::string& path, float lamp_cd_m2) {
  ImageRGBA scene(32, 32, 0.0f);
  for (int y = 14; y < 18; ++y)
    for (int x = 14; x < 18; ++x)
      for (int c = 0; c < 3; ++c) scene.pixel(x, y)[c] = lamp_cd_m2;
  write_exr(path, scene);
}

}  // namespace glarelab::test
