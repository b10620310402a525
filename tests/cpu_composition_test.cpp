// The stimulus frame composed on the CPU for the worker preparing a trial ahead
// (runner/session/cpu_composition.h) against the reference it stands in for: FrameRenderer's GL
// composition read back on the offscreen backend, bit for bit, for placements clipped, overlapping,
// partly off the frame and scaled in luminance; and a placement drawn at another size than its
// scene's, which only GL samples as GL does, is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/random.h"
#include "protocols/experiment.h"
#include "runner/display/display_backend.h"
#include "runner/session/cpu_composition.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

// A scene of luminances over six decades, from the project's seeded generator.
ImageRGBA random_scene(int width_px, int height_px, std::uint64_t stream) {
  ImageRGBA image(width_px, height_px);
  const CounterRandom random(20261129 + stream, RandomStream::glare_gl_test_input);
  std::uint64_t index = 0;
  for (float& value : image.rgba) value = static_cast<float>(std::pow(10.0, 6.0 * random.uniform(index++) - 3.0));
  return image;
}

TEST(CpuComposition, IsGlsCompositionBitForBit) {
  const int width = 160, height = 96;
  DisplayRequest request;
  request.width_px = width;
  request.height_px = height;
  const auto display = create_display("offscreen", request);
  FrameRenderer renderer(width, height);
  CpuComposition cpu(width, height);
  const ImageRGBA a = random_scene(50, 40, 1), b = random_scene(70, 30, 2);
  const SceneTexture ta = renderer.upload(a), tb = renderer.upload(b);
  cpu.add_scene(ta, a);
  cpu.add_scene(tb, b);
  const std::vector<std::vector<Placement>> layouts = {
      {},
      {{&ta, 1.0, {10, 20, 50, 40}, {0, 0, width, height}}},
      // Two columns, each clipped to its half; the second overlaps the first's rectangle.
      {{&ta, 4000.0, {30, 10, 50, 40}, {0, 0, 80, height}}, {&tb, 3076.92, {60, 50, 70, 30}, {80, 0, 80, height}}},
      // Partly off the frame on every side, drawn over one another in order.
      {{&tb, 0.37, {-20, -10, 70, 30}, {0, 0, width, height}}, {&ta, 123.456, {130, 70, 50, 40}, {0, 0, width, height}},
       {&ta, 6153.84, {5, 5, 50, 40}, {0, 0, width, height}}},
  };
  for (std::size_t i = 0; i < layouts.size(); ++i)
    for (const double background_cd_m2 : {0.0, 0.2513}) {
      ASSERT_TRUE(cpu.exact(layouts[i]));
      renderer.compose(layouts[i], background_cd_m2);
      const ImageRGBA gl = renderer.read_stimulus();
      const ImageRGBA composed = cpu.compose(layouts[i], background_cd_m2);
      ASSERT_EQ(composed.width_px, gl.width_px);
      ASSERT_EQ(composed.height_px, gl.height_px);
      EXPECT_EQ(composed.rgba, gl.rgba) << "layout " << i << ", background " << background_cd_m2;
    }
}

TEST(CpuComposition, TheDemosScenesComposeAsInGl) {
  const Experiment experiment = load_experiment(std::string(GLARELAB_SOURCE_DIR) + "/examples/demo.toml");
  const SceneLibrary scenes(experiment.scenes, experiment.display);
  const int width = experiment.display.width_px, height = experiment.display.height_px;
  DisplayRequest request;
  request.width_px = width;
  request.height_px = height;
  const auto display = create_display("offscreen", request);
  FrameRenderer renderer(width, height);
  CpuComposition cpu(width, height);
  const ImageRGBA& lamp = scenes.get("bright_4000").image_cd_m2;
  const SceneTexture texture = renderer.upload(lamp);
  cpu.add_scene(texture, lamp);
  // The demo's two columns, the reference and a comparison at 1.54 times it.
  const int x0 = width / 4 - lamp.width_px / 2, y0 = (height - lamp.height_px) / 2;
  const std::vector<Placement> placements = {
      {&texture, 4000.0, {x0, y0, lamp.width_px, lamp.height_px}, {0, 0, width / 2, height}},
      {&texture, 6153.84, {x0 + width / 2, y0, lamp.width_px, lamp.height_px}, {width / 2, 0, width / 2, height}}};
  ASSERT_TRUE(cpu.exact(placements));
  renderer.compose(placements, experiment.display.background_cd_m2);
  EXPECT_EQ(cpu.compose(placements, experiment.display.background_cd_m2).rgba, renderer.read_stimulus().rgba);
}

TEST(CpuComposition, RefusesAScaledPlacementOrAnUnknownScene) {
  const ImageRGBA a = random_scene(8, 6, 3);
  const SceneTexture known{}, unknown{};
  CpuComposition cpu(32, 32);
  cpu.add_scene(known, a);
  EXPECT_TRUE(cpu.exact({{&known, 2.0, {1, 2, 8, 6}, {0, 0, 32, 32}}}));
  EXPECT_FALSE(cpu.exact({{&known, 2.0, {1, 2, 16, 12}, {0, 0, 32, 32}}}));
  EXPECT_FALSE(cpu.exact({{&unknown, 2.0, {1, 2, 8, 6}, {0, 0, 32, 32}}}));
  EXPECT_THROW(cpu.compose({{&known, 2.0, {1, 2, 16, 12}, {0, 0, 32, 32}}}, 0.0), std::logic_error);
}

}  // namespace
}  // namespace glarelab
