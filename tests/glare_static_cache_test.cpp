// A static eye on a field luminance that changes every frame (the perception stages' adapted
// luminance) keeps a bounded cache of eyes and PSFs; a field luminance met again after the cache
// started over gives the same glare as the first time.
#include <gtest/gtest.h>

#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

TEST(GlareStaticCache, AFieldLuminanceMetAgainAfterManyOthersGivesTheSameGlare) {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  spec.skip_invisible = false;
  GlareStage stage(spec, display, 11);
  ImageRGBA frame(96, 64, 0.5f);
  for (int y = 28; y < 36; ++y)
    for (int x = 44; x < 52; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 500.0f;
  const ImageRGBA first = stage.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, 1.0);
  // More field luminances than the cache holds, each a different pupil.
  ImageRGBA last;
  for (int i = 1; i <= 40; ++i)
    last = stage.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, 1.0 + 0.5 * i);
  EXPECT_NE(last.rgba, first.rgba);
  const ImageRGBA again = stage.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, 1.0);
  EXPECT_EQ(again.rgba, first.rgba);
}

}  // namespace
}  // namespace glarelab
