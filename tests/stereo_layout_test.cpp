// The stereo layout (stimuli/stereo_layout.h) against hand-worked pixel numbers: each eye's view
// is its half of the display, the scenes are laid out in it as on a mono display of that size,
// overlays move to each view's centre, and the per-eye seeds are the counter-based generator's.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/random.h"
#include "stimuli/stereo_layout.h"

namespace glarelab {
namespace {

// Rectangles' shared pixels, worked by hand: an overlap, one inside the other, two that only
// touch along an edge (nothing shared), two apart.
TEST(PixelRectIntersection, SharedPixelsOrNone) {
  const PixelRect a{10, 20, 30, 40};  // x 10..39, y 20..59
  const PixelRect shared = intersection(a, PixelRect{30, 50, 100, 100});
  EXPECT_EQ(shared.x_px, 30);
  EXPECT_EQ(shared.y_px, 50);
  EXPECT_EQ(shared.width_px, 10);
  EXPECT_EQ(shared.height_px, 10);
  const PixelRect inside = intersection(a, PixelRect{12, 22, 3, 4});
  EXPECT_EQ(inside.x_px, 12);
  EXPECT_EQ(inside.y_px, 22);
  EXPECT_EQ(inside.width_px, 3);
  EXPECT_EQ(inside.height_px, 4);
  EXPECT_TRUE(intersection(a, PixelRect{40, 20, 5, 5}).empty());  // touches x = 40, the first column past a
  EXPECT_TRUE(intersection(a, PixelRect{100, 100, 5, 5}).empty());
  EXPECT_FALSE(a.empty());
}

DisplaySpec stereo_display(int width_px, int height_px) {
  DisplaySpec display;
  display.width_px = width_px;
  display.height_px = height_px;
  display.stereo = StereoMode::side_by_side;
  return display;
}

TEST(StereoLayoutTest, EachEyeSeesItsHalfNamedAsTrackersNumberThem) {
  DisplaySpec mono;
  EXPECT_TRUE(stereo_eye_views(mono).empty());
  const std::vector<EyeView> views = stereo_eye_views(stereo_display(1024, 512));
  ASSERT_EQ(views.size(), 2u);
  // Pupil Labs: eye 1 is the left eye, eye 0 the right.
  EXPECT_EQ(views[0].name, "left");
  EXPECT_EQ(views[0].tracker_eye, 1);
  EXPECT_EQ(views[0].viewport.x_px, 0);
  EXPECT_EQ(views[0].viewport.width_px, 512);
  EXPECT_EQ(views[1].name, "right");
  EXPECT_EQ(views[1].tracker_eye, 0);
  EXPECT_EQ(views[1].viewport.x_px, 512);
  EXPECT_EQ(views[1].viewport.width_px, 512);
  EXPECT_EQ(views[1].viewport.height_px, 512);
  const DisplaySpec eye = eye_display(stereo_display(1024, 512), views[1]);
  EXPECT_EQ(eye.width_px, 512);
  EXPECT_EQ(eye.height_px, 512);
  EXPECT_EQ(eye.stereo, StereoMode::none);
  EXPECT_EQ(eye.pixel_pitch_mm, DisplaySpec{}.pixel_pitch_mm);
  EXPECT_THROW(stereo_eye_views(stereo_display(1023, 512)), std::invalid_argument);
}

TEST(StereoLayoutTest, ScenesAreLaidOutInEachViewAsOnAMonoDisplayOfItsSize) {
  const std::vector<EyeView> views = stereo_eye_views(stereo_display(1024, 512));
  std::vector<PixelRect> columns;
  // Two 100 x 80 scenes: each view (512 wide) has columns 0..255 and 256..511; an image is centred
  // in its column: x = (256 - 100) / 2 = 78, y = (512 - 80) / 2 = 216.
  const std::vector<PixelRect> rects = stereo_layout(views, {{0, 0, 100, 80}, {0, 0, 100, 80}}, &columns);
  ASSERT_EQ(rects.size(), 4u);
  const int expected_x[] = {78, 256 + 78, 512 + 78, 512 + 256 + 78};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(rects[i].x_px, expected_x[i]) << i;
    EXPECT_EQ(rects[i].y_px, 216) << i;
    EXPECT_EQ(columns[i].width_px, 256) << i;
    EXPECT_EQ(columns[i].x_px, 256 * static_cast<int>(i)) << i;
  }
}

TEST(StereoLayoutTest, AStimulusWiderThanItsColumnInAnEyesHalfIsAMisfit) {
  const DisplaySpec display = stereo_display(1024, 512);
  EXPECT_EQ(stereo_misfit(display, {{0, 0, 512, 512}}, {"a"}), "");       // exactly half
  EXPECT_NE(stereo_misfit(display, {{0, 0, 513, 100}}, {"a"}).find("'a' (513 x 100 px) does not fit its column of 512 x 512 px"),
            std::string::npos);
  EXPECT_EQ(stereo_misfit(display, {{0, 0, 256, 100}, {0, 0, 256, 100}}, {"a", "b"}), "");
  EXPECT_NE(stereo_misfit(display, {{0, 0, 257, 100}, {0, 0, 257, 100}}, {"a", "b"}), "");
  EXPECT_NE(stereo_misfit(display, {{0, 0, 100, 513}}, {"a"}), "");  // taller than the display
  DisplaySpec mono = display;
  mono.stereo = StereoMode::none;
  EXPECT_EQ(stereo_misfit(mono, {{0, 0, 4000, 4000}}, {"a"}), "");
}

TEST(StereoLayoutTest, OverlaysMoveToTheCentreOfEachView) {
  const DisplaySpec display = stereo_display(1024, 512);
  const std::vector<EyeView> views = stereo_eye_views(display);
  // A 20 x 20 cross centred on the display (502..521) goes to the centre of each half:
  // 256 - 10 = 246 on the left, 768 - 10 = 758 on the right.
  const PixelRect cross{502, 246, 20, 20};
  EXPECT_EQ(moved_into_view(cross, display, views[0]).x_px, 246);
  EXPECT_EQ(moved_into_view(cross, display, views[1]).x_px, 758);
  EXPECT_EQ(moved_into_view(cross, display, views[1]).y_px, 246);
}

TEST(StereoLayoutTest, CropAndPasteAreInverse) {
  ImageRGBA frame(8, 2);
  for (std::size_t i = 0; i < frame.rgba.size(); ++i) frame.rgba[i] = static_cast<float>(i);
  const PixelRect right{4, 0, 4, 2};
  const ImageRGBA view = crop_view(frame, right);
  ASSERT_EQ(view.width_px, 4);
  EXPECT_EQ(view.pixel(0, 1)[0], frame.pixel(4, 1)[0]);
  ImageRGBA copy(8, 2);
  paste_view(copy, view, right);
  paste_view(copy, crop_view(frame, {0, 0, 4, 2}), {0, 0, 4, 2});
  EXPECT_EQ(copy.rgba, frame.rgba);
  EXPECT_THROW(crop_view(frame, {5, 0, 4, 2}), std::invalid_argument);
}

TEST(StereoLayoutTest, EyeSeedsComeFromTheCounterBasedGeneratorPerEye) {
  const std::uint64_t seed = 20261121;
  const auto bits = CounterRandom(seed, RandomStream::stereo_eye).bits(1);
  EXPECT_EQ(eye_seed(seed, 1), (static_cast<std::uint64_t>(bits[0]) << 32) | bits[1]);
  EXPECT_NE(eye_seed(seed, 0), eye_seed(seed, 1));
  EXPECT_EQ(eye_seed(seed, 0), eye_seed(seed, 0));
  EXPECT_NE(eye_seed(seed, 0), eye_seed(seed + 1, 0));
}

}  // namespace
}  // namespace glarelab
