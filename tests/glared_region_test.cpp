// Prepared glare frames kept as changed rectangles (runner/session/glared_region.h): the rectangle
// found against a hand-made frame, the bytes a 1080p trial's frames take against the bound, and
// what reaches the display: a frame kept at half precision encodes, through the renderer's real
// encode pass on the offscreen backend, to the same codes as the float32 frame, or to a
// neighbouring code, for the example scenes under glare at 8 (dithered) and 10 bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

#include "core/half_float.h"
#include "protocols/experiment.h"
#include "runner/display/display_backend.h"
#include "runner/session/glared_region.h"
#include "stimuli/frame_renderer.h"
#include "stimuli/glare_stage.h"
#include "stimuli/scene_library.h"

namespace glarelab {
namespace {

// A black frame with alpha 1, as a composed frame of the renderer holds.
ImageRGBA opaque_black(int width_px, int height_px) {
  ImageRGBA frame(width_px, height_px, 0.0f);
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) frame.pixel(x, y)[3] = 1.0f;
  return frame;
}

// A region's half-precision storage, once the region is gone, is the next region's of that size
// (no allocation, no zeroing, no page faults per frame), and holds that region's values only.
TEST(GlaredRegion, FreedHalfStorageIsReusedAndHoldsOnlyTheNewFrame) {
  const ImageRGBA composed = opaque_black(61, 47);
  ImageRGBA first = composed, second = composed;
  for (int y = 0; y < 47; ++y)
    for (int x = 0; x < 61; ++x)
      for (int c = 0; c < 3; ++c) {
        first.pixel(x, y)[c] = 1000.0f + static_cast<float>(x + 61 * y + c);
        second.pixel(x, y)[c] = 0.25f * static_cast<float>(x) + 0.5f * static_cast<float>(y) + static_cast<float>(c);
      }
  // An odd size, so that no storage another test freed fits it as well.
  const std::uint16_t* storage = nullptr;
  {
    const GlaredRegion region = changed_region(composed, first, RegionPrecision::half_rgb);
    ASSERT_EQ(region.half_rgb.size(), 3u * 61u * 47u);
    storage = region.half_rgb.data();
  }
  const GlaredRegion region = changed_region(composed, second, RegionPrecision::half_rgb);
  ASSERT_EQ(region.width_px, 61);
  ASSERT_EQ(region.height_px, 47);
  EXPECT_EQ(region.half_rgb.data(), storage) << "the freed region's storage was not reused";
  for (int y = 0; y < 47; ++y)
    for (int x = 0; x < 61; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(region.half_rgb[3 * (61 * static_cast<std::size_t>(46 - y) + x) + c],
                  half_from_float(second.pixel(x, y)[c]))
            << x << ", " << y << ", " << c;
}

TEST(GlaredRegion, KeepsTheChangedRectangleExactOrAtHalfPrecision) {
  const ImageRGBA composed = opaque_black(40, 30);
  ImageRGBA glared = composed;
  // Changed: (7, 5) and (20, 12) in different channels; the rectangle spans both.
  glared.pixel(7, 5)[0] = 3.14159f;
  glared.pixel(20, 12)[2] = 1234.567f;
  const GlaredRegion exact = changed_region(composed, glared, RegionPrecision::exact);
  EXPECT_EQ(exact.x0_px, 7);
  EXPECT_EQ(exact.y0_px, 5);
  EXPECT_EQ(exact.width_px, 14);
  EXPECT_EQ(exact.height_px, 8);
  EXPECT_TRUE(exact.half_rgb.empty());
  EXPECT_EQ(exact.exact_rgba.size(), 14u * 8u * 4u);
  EXPECT_EQ(exact.bytes(), 14u * 8u * 16u);
  const ImageRGBA exact_pixels = region_pixels(exact);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 14; ++x)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(exact_pixels.pixel(x, y)[c], glared.pixel(7 + x, 5 + y)[c]);

  const GlaredRegion half = changed_region(composed, glared, RegionPrecision::half_rgb);
  EXPECT_EQ(half.x0_px, 7);
  EXPECT_EQ(half.width_px, 14);
  EXPECT_TRUE(half.exact_rgba.empty());
  EXPECT_EQ(half.bytes(), 14u * 8u * 6u);
  // Rows bottom-up: the region's top row (y = 5) is the last in memory.
  EXPECT_EQ(half.half_rgb[3 * 14 * 7 + 0], half_from_float(3.14159f));
  const ImageRGBA half_pixels = region_pixels(half);
  EXPECT_NEAR(half_pixels.pixel(0, 0)[0], 3.14159f, 3.14159f * std::ldexp(1.0f, -11));
  EXPECT_NEAR(half_pixels.pixel(13, 7)[2], 1234.567f, 1234.567f * std::ldexp(1.0f, -11));
  EXPECT_EQ(half_pixels.pixel(13, 7)[3], 1.0f);

  EXPECT_TRUE(changed_region(composed, composed, RegionPrecision::half_rgb).empty());
}

// A frame's change since the frame before it (what a flip that follows that frame's draws): the
// box of the pixels whose halves differ, in frame coordinates, against two hand-made frames of the
// same rectangle; nothing when they are the same; unknown against a region of another rectangle
// or precision.
TEST(GlaredRegion, ChangesSinceThePreviousFrameAreTheBoxOfTheHalvesThatDiffer) {
  const ImageRGBA composed = opaque_black(40, 30);
  ImageRGBA before = composed;
  // Both frames differ from the composed one in (3, 2) to (30, 25): the same region rectangle.
  for (int y = 2; y <= 25; ++y)
    for (int x = 3; x <= 30; ++x) before.pixel(x, y)[1] = 0.5f + 0.01f * static_cast<float>(x + y);
  ImageRGBA after = before;
  after.pixel(9, 20)[0] = 77.0f;   // the box's left and bottom edges
  after.pixel(15, 6)[2] = 0.125f;  // its right and top edges
  after.pixel(12, 10)[1] += 1e-6f;  // below a half's step at 0.72: the same half, no change
  const GlaredRegion first = changed_region(composed, before, RegionPrecision::half_rgb);
  GlaredRegion second = changed_region(composed, after, RegionPrecision::half_rgb);
  ASSERT_EQ(first.x0_px, 3);
  ASSERT_EQ(second.x0_px, 3);
  ASSERT_EQ(second.height_px, first.height_px);
  EXPECT_EQ(second.previous_serial, 0u);
  mark_changes_since(second, first);
  EXPECT_EQ(second.previous_serial, first.serial);
  EXPECT_EQ(second.changed_since_previous, (PixelRect{9, 6, 7, 15}));

  GlaredRegion same = changed_region(composed, before, RegionPrecision::half_rgb);
  mark_changes_since(same, first);
  EXPECT_EQ(same.previous_serial, first.serial);
  EXPECT_TRUE(same.changed_since_previous.empty());

  // Another rectangle (one more pixel changed): not known.
  ImageRGBA wider = after;
  wider.pixel(35, 20)[0] = 1.0f;
  GlaredRegion other_rect = changed_region(composed, wider, RegionPrecision::half_rgb);
  mark_changes_since(other_rect, first);
  EXPECT_EQ(other_rect.previous_serial, 0u);
  // After frame 0's exact region: its values compared as the halves they round to, so the same box
  // (the 1e-6 at (12, 10) still rounds to the same half).
  const GlaredRegion exact_before = changed_region(composed, before, RegionPrecision::exact);
  GlaredRegion after_exact = changed_region(composed, after, RegionPrecision::half_rgb);
  mark_changes_since(after_exact, exact_before);
  EXPECT_EQ(after_exact.previous_serial, exact_before.serial);
  EXPECT_EQ(after_exact.changed_since_previous, (PixelRect{9, 6, 7, 15}));
  // An exact region the half region is not compared with: one of another rectangle, and a half
  // region is never compared into an exact one.
  GlaredRegion after_other = changed_region(composed, after, RegionPrecision::half_rgb);
  mark_changes_since(after_other, changed_region(composed, wider, RegionPrecision::exact));
  EXPECT_EQ(after_other.previous_serial, 0u);
  GlaredRegion exact_after = changed_region(composed, after, RegionPrecision::exact);
  mark_changes_since(exact_after, first);
  EXPECT_EQ(exact_after.previous_serial, 0u);
}

// Given the box the differences lie in (the glare reports' changed boxes), the same rectangle and
// pixels as the whole-frame comparison, for boxes tight, loose, partly outside the frame and empty.
TEST(GlaredRegion, ABoxTheDifferencesLieInGivesTheSameRegion) {
  const ImageRGBA composed = opaque_black(64, 48);
  ImageRGBA glared = composed;
  glared.pixel(10, 7)[1] = 2.5f;
  glared.pixel(31, 20)[0] = 7.0f;
  glared.pixel(18, 29)[3] = 0.5f;  // alpha counts too
  for (const RegionPrecision precision : {RegionPrecision::exact, RegionPrecision::half_rgb}) {
    const GlaredRegion whole = changed_region(composed, glared, precision);
    ASSERT_EQ(whole.x0_px, 10);
    ASSERT_EQ(whole.y0_px, 7);
    ASSERT_EQ(whole.width_px, 22);
    ASSERT_EQ(whole.height_px, 23);
    for (const PixelRect box : {PixelRect{10, 7, 22, 23}, PixelRect{2, 3, 50, 40}, PixelRect{-20, -5, 200, 100}}) {
      const GlaredRegion bounded = changed_region(composed, glared, precision, box);
      EXPECT_EQ(bounded.x0_px, whole.x0_px);
      EXPECT_EQ(bounded.y0_px, whole.y0_px);
      EXPECT_EQ(bounded.width_px, whole.width_px);
      EXPECT_EQ(bounded.height_px, whole.height_px);
      EXPECT_EQ(bounded.exact_rgba, whole.exact_rgba);
      EXPECT_EQ(bounded.half_rgb, whole.half_rgb);
    }
  }
  // The box is what is compared: a difference left outside it is not looked for.
  EXPECT_EQ(changed_region(composed, glared, RegionPrecision::exact, PixelRect{0, 0, 20, 20}).width_px, 1);
  EXPECT_TRUE(changed_region(composed, glared, RegionPrecision::exact, PixelRect{0, 0, 0, 0}).empty());
  EXPECT_TRUE(changed_region(composed, composed, RegionPrecision::exact, PixelRect{10, 7, 22, 23}).empty());
}

// Each region changed_region() makes has its own serial (a flip of the region the framebuffer
// already holds only re-encodes it: SessionLoop::draw); a copy, with the same pixels, keeps it.
// A frame's halves are made four values at a time where the processor has F16C: every value kept
// is half_from_float's, bit for bit, across the float range (a walk over bit patterns: every
// exponent, subnormals, infinities, NaNs) and at the edges (ties to even, the clamp at 65520, the
// smallest subnormal half and the float below half of it).
TEST(GlaredRegion, HalfPrecisionKeepsHalfFromFloatsBitsForEveryValue) {
  const int width = 67, height = 53;
  ImageRGBA composed = opaque_black(width, height), glared = composed;
  const float edges[] = {1.0f + 0x1p-11f,  1.0f + 0x3p-11f, -(1.0f + 0x1p-11f), 65503.9f, 65504.0f, 65519.99f,
                         65520.0f,         70000.0f,        -1e9f,              INFINITY, -INFINITY, NAN,
                         -NAN,             0x1p-14f,        0x1p-24f,           0x1p-25f, 0x1.8p-25f, 1e-40f,
                         -0.0f,            0.5f,            4000.0f,            0x1.ffep-15f};
  std::uint32_t bits = 0x3f800000u;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c) {
        const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4 + c;
        bits = bits * 1664525u + 1013904223u;  // a fixed walk over the 32-bit patterns
        glared.rgba[i] = i < std::size(edges) * 4 && c < 3 ? edges[i / 4 % std::size(edges)] * (c == 2 ? -1.0f : 1.0f)
                                                           : std::bit_cast<float>(bits);
      }
  glared.pixel(0, 0)[0] = 1.0f;  // the region is the whole frame
  glared.pixel(width - 1, height - 1)[0] = 1.0f;
  const GlaredRegion region = changed_region(composed, glared, RegionPrecision::half_rgb);
  ASSERT_EQ(region.width_px, width);
  ASSERT_EQ(region.height_px, height);
  int nan = 0, clamped = 0, subnormal = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float value = glared.pixel(x, y)[c];
        const std::uint16_t kept = region.half_rgb[3 * (width * static_cast<std::size_t>(height - 1 - y) + x) + c];
        ASSERT_EQ(kept, half_from_float(value)) << x << ", " << y << ", " << c << ": " << value;
        nan += std::isnan(value);
        clamped += !std::isnan(value) && std::abs(value) >= 65520.0f;
        subnormal += std::abs(value) > 0.0f && std::abs(value) < 0x1p-14f;
      }
  // The walk reaches the cases the fast path hands back, and subnormal halves.
  EXPECT_GT(nan, 10);
  EXPECT_GT(clamped, 100);
  EXPECT_GT(subnormal, 10);
}

TEST(GlaredRegion, EveryRegionMadeHasItsOwnSerialAndACopyKeepsIt) {
  const ImageRGBA composed(8, 6, 1.0f);
  ImageRGBA glared = composed;
  glared.pixel(3, 2)[0] = 2.0f;
  const GlaredRegion first = changed_region(composed, glared, RegionPrecision::exact);
  const GlaredRegion again = changed_region(composed, glared, RegionPrecision::exact);
  const GlaredRegion unchanged = changed_region(composed, composed, RegionPrecision::half_rgb);
  EXPECT_NE(first.serial, 0u);
  EXPECT_NE(again.serial, 0u);
  EXPECT_NE(unchanged.serial, 0u);
  EXPECT_NE(first.serial, again.serial) << "the same pixels made twice are two regions";
  EXPECT_NE(again.serial, unchanged.serial);
  const GlaredRegion copy = first;
  EXPECT_EQ(copy.serial, first.serial);
  EXPECT_EQ(GlaredRegion{}.serial, 0u) << "a region not made by changed_region is never taken as drawn";
}

TEST(GlaredRegion, A1080pTrialsFramesFitTheBoundAndTakeUnderFourTenthsOfFloat32) {
  // Worst case: glare changes every pixel of every frame (a stimulus filling the display).
  constexpr int kWidth = 1920, kHeight = 1080, kFrames = 30;
  const ImageRGBA composed(kWidth, kHeight, 1.0f);
  const ImageRGBA glared(kWidth, kHeight, 2.0f);
  // A trial keeps frame 0 exact and the others at half precision (runner/session/trial_glare.cpp).
  const std::size_t store = changed_region(composed, glared, RegionPrecision::exact).bytes() +
                            (kFrames - 1) * changed_region(composed, glared, RegionPrecision::half_rgb).bytes();
  const std::size_t pixels = std::size_t{kWidth} * kHeight;
  EXPECT_EQ(store, pixels * (16 + (kFrames - 1) * 6));
  EXPECT_LE(store, prepared_frames_bound_bytes(kWidth, kHeight, kFrames));
  EXPECT_EQ(prepared_frames_bound_bytes(kWidth, kHeight, kFrames), pixels * (16 + (kFrames - 1) * 6));
  const std::size_t float32_frames = kFrames * pixels * 4 * sizeof(float);  // 995 MB
  EXPECT_LT(static_cast<double>(store), 0.4 * static_cast<double>(float32_frames));
}

// --- what the display shows ---

struct Codes {
  int largest_difference = 0;
  long differing = 0;
  long values = 0;
};

// The display codes of two read-back display frames (R, G, B of every pixel at `levels` + 1 codes)
// against each other.
Codes compared_codes(const ImageRGBA& reference, const ImageRGBA& shown, double levels) {
  Codes codes;
  for (int y = 0; y < reference.height_px; ++y)
    for (int x = 0; x < reference.width_px; ++x)
      for (int c = 0; c < 3; ++c) {
        const long a = std::lround(reference.pixel(x, y)[c] * levels);
        const long b = std::lround(shown.pixel(x, y)[c] * levels);
        codes.largest_difference = std::max(codes.largest_difference, static_cast<int>(std::abs(a - b)));
        codes.differing += a != b;
        ++codes.values;
      }
  return codes;
}

class HalfFramesOnTheDisplay : public ::testing::TestWithParam<std::string> {};

// The example's first two scenes side by side (each centred in its half of the display) on its
// background, as a session composes a side-by-side trial, in cd/m2.
ImageRGBA side_by_side(const Experiment& experiment, const SceneLibrary& scenes) {
  const DisplaySpec& display = experiment.display;
  ImageRGBA frame(display.width_px, display.height_px, static_cast<float>(display.background_cd_m2));
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) frame.pixel(x, y)[3] = 1.0f;
  int slot = 0;
  for (const auto& [name, scene] : scenes.scenes()) {
    if (slot == 2) break;
    const ImageRGBA& image = scene.image_cd_m2;
    const int x0 = slot * frame.width_px / 2 + (frame.width_px / 2 - image.width_px) / 2;
    const int y0 = (frame.height_px - image.height_px) / 2;
    for (int y = 0; y < image.height_px; ++y)
      for (int x = 0; x < image.width_px; ++x)
        if (x0 + x >= 0 && x0 + x < frame.width_px && y0 + y >= 0 && y0 + y < frame.height_px)
          std::copy_n(image.pixel(x, y), 4, frame.pixel(x0 + x, y0 + y));
    ++slot;
  }
  return frame;
}

// An example's display offscreen with its renderer, its first two scenes composed side by side,
// and its glare stage on the CPU.
struct ExampleOnTheDisplay {
  explicit ExampleOnTheDisplay(const std::string& file)
      : experiment(load_experiment(std::string(GLARELAB_SOURCE_DIR) + "/examples/" + file)),
        scenes(experiment.scenes, experiment.display),
        width(experiment.display.width_px),
        height(experiment.display.height_px),
        display(create_display("offscreen", request(width, height))),
        renderer(width, height),
        composed(side_by_side(experiment, scenes)),
        glare(experiment.glare, experiment.display, experiment.seed) {}
  static DisplayRequest request(int width_px, int height_px) {
    DisplayRequest r;
    r.width_px = width_px;
    r.height_px = height_px;
    return r;
  }
  const Experiment experiment;
  const SceneLibrary scenes;
  const int width, height;
  const std::unique_ptr<DisplayBackend> display;
  FrameRenderer renderer;
  const ImageRGBA composed;
  GlareStage glare;  // no GL: the CPU path
};

TEST_P(HalfFramesOnTheDisplay, EncodeToTheFloat32FramesCodesOrANeighbour) {
  ExampleOnTheDisplay on(GetParam());
  const Experiment& experiment = on.experiment;
  const auto& display = on.display;
  FrameRenderer& renderer = on.renderer;
  const ImageRGBA& composed = on.composed;
  GlareStage& glare = on.glare;

  const auto shown = [&](const ImageRGBA* whole, const GlaredRegion* region, const DisplaySpec& spec) {
    if (whole != nullptr) renderer.replace_stimulus(*whole);
    if (region != nullptr) {
      renderer.replace_stimulus(composed);
      renderer.replace_stimulus_region_half_rgb(region->half_rgb, region->x0_px, region->y0_px, region->width_px,
                                                region->height_px);
    }
    renderer.encode_to_display(spec);
    display->present();
    return renderer.read_display();
  };
  for (const double time_s : {0.1, 0.35}) {
    // A dynamic eye's frame, as a session prepares it.
    const ImageRGBA glared = glare.apply(composed, GlareMode::dynamic, time_s);
    const GlaredRegion region = changed_region(composed, glared, RegionPrecision::half_rgb);
    ASSERT_FALSE(region.empty());
    ASSERT_GT(region.width_px * region.height_px, 1000) << "glare changes the stimuli and their surround";
    // Frame 0's exact region over the composed frame is the glared frame, bit for bit.
    const GlaredRegion exact = changed_region(composed, glared, RegionPrecision::exact);
    renderer.replace_stimulus(composed);
    renderer.replace_stimulus_region_bottom_up(exact.exact_rgba, exact.x0_px, exact.y0_px, exact.width_px,
                                               exact.height_px);
    EXPECT_EQ(renderer.read_stimulus().rgba, glared.rgba);
    for (const DisplayEncoding encoding : {experiment.display.encoding, DisplayEncoding::pq}) {
      for (const int bits : {8, 10}) {
        SCOPED_TRACE("t " + std::to_string(time_s) + " s, " + (encoding == DisplayEncoding::pq ? "pq" : "file's encoding") +
                     ", " + std::to_string(bits) + " bits");
        DisplaySpec spec = experiment.display;
        spec.encoding = encoding;
        spec.bits_per_channel = bits;  // 8: RGBA8 with 4x4 ordered dithering (stimuli/frame_renderer.h)
        const double levels = std::ldexp(1.0, bits) - 1.0;
        const ImageRGBA reference = shown(&glared, nullptr, spec);
        const ImageRGBA half = shown(nullptr, &region, spec);
        const Codes codes = compared_codes(reference, half, levels);
        EXPECT_LE(codes.largest_difference, 1);
        // Half's step (2^-11 relative) is a small fraction of a code, so few values sit close
        // enough to a code boundary (or a dither threshold) to cross it.
        EXPECT_LT(static_cast<double>(codes.differing), 0.01 * static_cast<double>(codes.values));
        std::cout << GetParam() << " t " << time_s << " s " << (encoding == DisplayEncoding::pq ? "pq" : "file") << " "
                  << bits << " bits: " << codes.differing << " of " << codes.values << " values one code apart\n";
      }
    }
  }
}

// Frame 1 of a dynamic interval drawn over frame 0's exact region as a session draws it: only the
// box where its halves differ from those frame 0's values round to is written
// (GlaredRegion::changed_since_previous), and the rest of the framebuffer keeps frame 0's float32
// values. Every code shown is frame 1's exact code or a neighbour, as for a frame drawn whole.
// The demo's moving eye (Spencer's analytic glare, the other example above, does not move).
TEST(HalfFrameOverAnExactFrame, TheDemosFrameOneWrittenWhereItsHalvesDifferShowsItsCodesOrANeighbour) {
  ExampleOnTheDisplay on("demo.toml");
  const Experiment& experiment = on.experiment;
  const auto& display = on.display;
  FrameRenderer& renderer = on.renderer;
  const ImageRGBA& composed = on.composed;
  GlareStage& glare = on.glare;
  const double period_s = 1.0 / experiment.display.refresh_hz;
  const ImageRGBA frame_0 = glare.apply(composed, GlareMode::dynamic, 0.1);
  const ImageRGBA frame_1 = glare.apply(composed, GlareMode::dynamic, 0.1 + period_s);
  const GlaredRegion exact_0 = changed_region(composed, frame_0, RegionPrecision::exact);
  GlaredRegion half_1 = changed_region(composed, frame_1, RegionPrecision::half_rgb);
  mark_changes_since(half_1, exact_0);
  ASSERT_EQ(half_1.previous_serial, exact_0.serial) << "the two frames' regions share their rectangle";
  const PixelRect part = half_1.changed_since_previous;
  ASSERT_FALSE(part.empty()) << "the moving eye changes the glare from frame to frame";
  std::cout << "demo: frame 1 writes " << part.width_px << " x " << part.height_px << " of its "
            << half_1.width_px << " x " << half_1.height_px << " region\n";

  for (const DisplayEncoding encoding : {experiment.display.encoding, DisplayEncoding::pq}) {
    for (const int bits : {8, 10}) {
      SCOPED_TRACE(std::string(encoding == DisplayEncoding::pq ? "pq" : "file's encoding") + ", " +
                   std::to_string(bits) + " bits");
      DisplaySpec spec = experiment.display;
      spec.encoding = encoding;
      spec.bits_per_channel = bits;
      const double levels = std::ldexp(1.0, bits) - 1.0;
      renderer.replace_stimulus(frame_1);
      renderer.encode_to_display(spec);
      display->present();
      const ImageRGBA reference = renderer.read_display();
      renderer.replace_stimulus(composed);
      renderer.replace_stimulus_region_bottom_up(exact_0.exact_rgba, exact_0.x0_px, exact_0.y0_px, exact_0.width_px,
                                                 exact_0.height_px);
      renderer.replace_stimulus_region_half_rgb_part(half_1.half_rgb, half_1.x0_px, half_1.y0_px, half_1.width_px,
                                                     half_1.height_px, part);
      renderer.encode_to_display(spec);
      display->present();
      const ImageRGBA drawn = renderer.read_display();
      const Codes codes = compared_codes(reference, drawn, levels);
      EXPECT_LE(codes.largest_difference, 1);
      EXPECT_LT(static_cast<double>(codes.differing), 0.01 * static_cast<double>(codes.values));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, HalfFramesOnTheDisplay, ::testing::Values("demo.toml", "spencer_staircase.toml"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return param.param.substr(0, param.param.find('.'));
                         });

}  // namespace
}  // namespace glarelab
