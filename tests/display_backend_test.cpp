// Both display backends render a known pattern and read it back as floats. The offscreen tests run
// everywhere; the WindowBackend tests need an X display and run under Xvfb (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/half_float.h"
#include "runner/display/display_backend.h"
#include "stimuli/display_model.h"
#include "stimuli/frame_renderer.h"

namespace glarelab {
namespace {

// A scene whose pixels encode their own position, over a wide luminance range, so any
// misplacement, flip or precision loss shows.
ImageRGBA position_pattern(int width, int height) {
  ImageRGBA image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float* p = image.pixel(x, y);
      p[0] = static_cast<float>(x) + 0.25f;
      p[1] = static_cast<float>(y) + 0.5f;
      p[2] = std::pow(10.0f, static_cast<float>((x + y) % 12) - 3.0f);  // 1e-3 .. 1e8 cd/m2
      p[3] = 1.0f;
    }
  return image;
}

void check_backend_renders_pattern(DisplayBackend& display) {
  const int width = display.width_px();
  const int height = display.height_px();
  FrameRenderer renderer(width, height);
  const ImageRGBA pattern = position_pattern(24, 16);
  const SceneTexture scene = renderer.upload(pattern);
  const PixelRect rect{10, 7, pattern.width_px, pattern.height_px};
  ASSERT_GE(width, rect.x_px + rect.width_px);
  ASSERT_GE(height, rect.y_px + rect.height_px);
  renderer.compose({{&scene, 2.0, rect, {0, 0, width, height}}}, 0.125);

  const ImageRGBA stimulus = renderer.read_stimulus();
  ASSERT_EQ(stimulus.width_px, width);
  for (int y = 0; y < pattern.height_px; ++y)
    for (int x = 0; x < pattern.width_px; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(stimulus.pixel(rect.x_px + x, rect.y_px + y)[c], 2.0f * pattern.pixel(x, y)[c])
            << "pixel " << x << "," << y << " channel " << c;
  EXPECT_EQ(stimulus.pixel(0, 0)[0], 0.125f);                  // background, top-left
  EXPECT_EQ(stimulus.pixel(width - 1, height - 1)[1], 0.125f);  // background, bottom-right

  // Display encoding against the CPU reference (IEC 61966-2-1), for an sRGB display of 100 cd/m2.
  DisplaySpec spec;
  spec.peak_luminance_cd_m2 = 100.0;
  spec.encoding = DisplayEncoding::srgb;
  renderer.encode_to_display(spec);
  display.present();
  const ImageRGBA shown = renderer.read_display();
  const DisplayModel model(spec);
  // The default framebuffer may be 8 bits per channel (window), half float (an EGL pbuffer: 11
  // significant bits; llvmpipe converts by truncation, so up to one unit in the last place, 2^-11
  // below 1) or float (OSMesa).
  const std::string& platform = display.gl_info().platform;
  const double tolerance = display.kind() == "window"                        ? 0.5 / 255.0 + 1e-6
                           : platform.find("RGBA16F") != std::string::npos ? std::ldexp(1.0, -11) + 1e-7
                           : platform.find("RGBA8") != std::string::npos   ? 0.5 / 255.0 + 1e-6
                                                                           : 1e-5;
  for (int y = 0; y < pattern.height_px; ++y)
    for (int x = 0; x < pattern.width_px; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(shown.pixel(rect.x_px + x, rect.y_px + y)[c], model.encode(2.0 * pattern.pixel(x, y)[c]), tolerance)
            << "pixel " << x << "," << y << " channel " << c;
}

// Each headless path on its own ("egl", "osmesa") and the one --display offscreen picks.
class HeadlessBackend : public ::testing::TestWithParam<std::string> {};

TEST_P(HeadlessBackend, RendersKnownPatternInFloat) {
  DisplayRequest request;
  request.width_px = 64;
  request.height_px = 48;
  auto display = create_display(GetParam(), request);
  EXPECT_EQ(display->kind(), "offscreen");
  EXPECT_GE(display->gl_info().major * 10 + display->gl_info().minor, 45) << display->gl_info().describe();
  const std::string& platform = display->gl_info().platform;
  // Where EGL starts (it does on this project's machines), offscreen takes it.
  if (GetParam() == "osmesa") {
    EXPECT_EQ(platform, "OSMesa");
  } else {
    EXPECT_EQ(platform.rfind("EGL ", 0), 0u) << platform;
  }
  check_backend_renders_pattern(*display);
}

// Two contexts of one kind at once (a session's display and the GL glare engine's own): each draws
// correctly after the other was current.
TEST_P(HeadlessBackend, TwoContextsTakeTurns) {
  DisplayRequest request;
  request.width_px = 40;
  request.height_px = 30;
  auto first = create_display(GetParam(), request);
  auto second = create_display(GetParam(), request);
  first->make_current();
  check_backend_renders_pattern(*first);
  second->make_current();
  check_backend_renders_pattern(*second);
  second.reset();
  first->make_current();
  check_backend_renders_pattern(*first);
}

// An offscreen display keeps the frame drawn into it across presents, which a session relies on to
// skip encoding an unchanged stimulus again (SessionLoop::encode): the encoded frame read back after
// more presents, and after drawing the stimulus framebuffer anew, is the one encoded first.
TEST_P(HeadlessBackend, KeepsThePresentedFrameAcrossPresents) {
  DisplayRequest request;
  request.width_px = 48;
  request.height_px = 32;
  auto display = create_display(GetParam(), request);
  EXPECT_TRUE(display->keeps_presented_frame());
  FrameRenderer renderer(request.width_px, request.height_px);
  const ImageRGBA pattern = position_pattern(24, 16);
  const SceneTexture scene = renderer.upload(pattern);
  renderer.compose({{&scene, 0.5, {8, 6, 24, 16}, {0, 0, request.width_px, request.height_px}}}, 0.25);
  DisplaySpec spec;
  spec.peak_luminance_cd_m2 = 100.0;
  renderer.encode_to_display(spec);
  display->present();
  const ImageRGBA first = renderer.read_display();
  display->present();
  display->present();
  EXPECT_EQ(renderer.read_display().rgba, first.rgba) << "presents alone change nothing";
  renderer.compose({}, 50.0);  // the stimulus framebuffer drawn anew, the display's not encoded
  display->present();
  EXPECT_EQ(renderer.read_display().rgba, first.rgba) << "only an encode writes the display's framebuffer";
  renderer.encode_to_display(spec);
  EXPECT_NE(renderer.read_display().rgba, first.rgba) << "the check can fail: a new encode shows";
}

INSTANTIATE_TEST_SUITE_P(Display, HeadlessBackend, ::testing::Values("egl", "osmesa", "offscreen"));

// The session re-encodes a flip of an unchanged frame without composing it again when the
// renderer's write count is the one it left (runner/session/trial_presentation.cpp): every write
// to the stimulus framebuffer must count, and reading or encoding must not.
// An offscreen display keeps its encoded frame, so after a change only the changed pixels are
// encoded again: the display then holds, bit for bit, what encoding the whole frame gives, for a
// float target, a dithered 8-bit one, a 10-bit one and PQ. The changed rectangle is the bounding
// box of the writes since the last encode (reads write nothing).
TEST(FrameRendererWrites, EncodingOnlyWhatChangedEqualsEncodingTheWholeFrame) {
  DisplayRequest request;
  request.width_px = 48;
  request.height_px = 32;
  auto display = create_display("offscreen", request);
  for (const int bits : {0, 8, 10}) {
    for (const DisplayEncoding encoding : {DisplayEncoding::srgb, DisplayEncoding::pq}) {
      FrameRenderer renderer(48, 32);
      const ImageRGBA pattern = position_pattern(16, 8);
      const SceneTexture scene = renderer.upload(pattern);
      DisplaySpec spec;
      spec.peak_luminance_cd_m2 = 100.0;
      spec.bits_per_channel = bits;
      spec.encoding = encoding;
      const std::vector<Placement> overlay = {{&scene, 0.5, {10, 4, 16, 8}, {0, 0, 48, 32}}};
      renderer.compose({{&scene, 1.0, {2, 3, 16, 8}, {0, 0, 48, 32}}}, 0.5);
      renderer.compose_overlay(overlay);
      renderer.encode_changes_to_display(spec);  // the first: the whole frame
      EXPECT_EQ(renderer.unencoded_rect().width_px, 0);
      // A new region under part of the overlay, the overlay blended again inside it only.
      ImageRGBA region = position_pattern(12, 10);
      for (float& value : region.rgba) value *= 3.0f;
      for (std::size_t k = 3; k < region.rgba.size(); k += 4) region.rgba[k] = 1.0f;
      renderer.replace_stimulus_region(region, 20, 6);
      renderer.compose_overlay({{&scene, 0.5, {10, 4, 16, 8}, {20, 6, 6, 6}}});
      // What a session's dynamic glare flip leaves in the stimulus (no new compose, the overlay
      // blended again inside the region only) is what composing it all afresh gives.
      {
        FrameRenderer fresh(48, 32);
        const SceneTexture fresh_scene = fresh.upload(pattern);
        fresh.compose({{&fresh_scene, 1.0, {2, 3, 16, 8}, {0, 0, 48, 32}}}, 0.5);
        fresh.replace_stimulus_region(region, 20, 6);
        fresh.compose_overlay({{&fresh_scene, 0.5, {10, 4, 16, 8}, {0, 0, 48, 32}}});
        EXPECT_EQ(renderer.read_stimulus().rgba, fresh.read_stimulus().rgba);
      }
      const PixelRect changed = renderer.unencoded_rect();
      EXPECT_EQ(changed.x_px, 20);
      EXPECT_EQ(changed.y_px, 6);
      EXPECT_EQ(changed.width_px, 12);
      EXPECT_EQ(changed.height_px, 10);
      renderer.encode_changes_to_display(spec);
      renderer.encode_changes_to_display(spec);  // nothing changed since: nothing encoded
      const ImageRGBA incremental = renderer.read_display();
      renderer.encode_to_display(spec);
      const ImageRGBA whole = renderer.read_display();
      ASSERT_EQ(incremental.rgba.size(), whole.rgba.size());
      EXPECT_EQ(incremental.rgba, whole.rgba) << bits << " bits, encoding " << static_cast<int>(encoding);
      // And the region did change the display (the test would not notice a missing encode otherwise).
      renderer.replace_stimulus_region(pattern, 20, 6);
      renderer.encode_to_display(spec);
      EXPECT_NE(renderer.read_display().rgba, whole.rgba);
    }
  }
}

// A dynamic glare flip that follows the frame before it writes only the part of its half region
// that differs from that frame's (read in place from the region's rows), blends the overlays
// again inside that part and encodes it: the stimulus and the display then hold, bit for bit, what
// writing the whole region into a freshly composed frame gives, for a float and a dithered 8-bit
// target. A part outside its region is refused.
TEST(FrameRendererWrites, APartOfAHalfRegionLeavesWhatTheWholeRegionWouldHave) {
  DisplayRequest request;
  request.width_px = 48;
  request.height_px = 32;
  auto display = create_display("offscreen", request);
  // Two half regions of 30 x 20 at (6, 5), rows bottom-up, the second differing from the first in
  // the region's columns 4 to 16 and rows 7 to 15 from the top (frame (10, 12), 13 x 9).
  const int x0 = 6, y0 = 5, width = 30, height = 20;
  std::vector<std::uint16_t> first(3 * width * height), second;
  for (std::size_t i = 0; i < first.size(); ++i)
    first[i] = half_from_float(0.37f * static_cast<float>(i % 97) + 0.01f * static_cast<float>(i / 97));
  second = first;
  const PixelRect part{10, 12, 13, 9};
  for (int y = 7; y < 16; ++y)
    for (int x = 4; x < 17; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t row_from_bottom = static_cast<std::size_t>(height - 1 - y);
        second[3 * (row_from_bottom * width + x) + c] = half_from_float(40.0f + static_cast<float>(x * 3 + y + c));
      }
  for (const int bits : {0, 8}) {
    DisplaySpec spec;
    spec.peak_luminance_cd_m2 = 100.0;
    spec.bits_per_channel = bits;
    FrameRenderer renderer(48, 32);
    const SceneTexture scene = renderer.upload(position_pattern(16, 8));
    const std::vector<Placement> placements = {{&scene, 1.0, {2, 3, 16, 8}, {0, 0, 48, 32}}};
    const Placement overlay{&scene, 0.5, {14, 10, 16, 8}, {0, 0, 48, 32}};
    renderer.compose(placements, 0.5);
    renderer.replace_stimulus_region_half_rgb(first, x0, y0, width, height);
    renderer.compose_overlay({overlay});
    renderer.encode_changes_to_display(spec);
    Placement overlay_in_part = overlay;
    overlay_in_part.clip = part;
    renderer.replace_stimulus_region_half_rgb_part(second, x0, y0, width, height, part);
    renderer.compose_overlay({overlay_in_part});
    EXPECT_EQ(renderer.unencoded_rect(), part);
    renderer.encode_changes_to_display(spec);

    FrameRenderer fresh(48, 32);
    const SceneTexture fresh_scene = fresh.upload(position_pattern(16, 8));
    Placement fresh_overlay = overlay;
    fresh_overlay.scene = &fresh_scene;
    fresh.compose({{&fresh_scene, 1.0, {2, 3, 16, 8}, {0, 0, 48, 32}}}, 0.5);
    fresh.replace_stimulus_region_half_rgb(second, x0, y0, width, height);
    fresh.compose_overlay({fresh_overlay});
    fresh.encode_to_display(spec);
    EXPECT_EQ(renderer.read_stimulus().rgba, fresh.read_stimulus().rgba) << bits << " bits";
    EXPECT_EQ(renderer.read_display().rgba, fresh.read_display().rgba) << bits << " bits";
    // And the part did change the frame (a missing write would pass the comparisons otherwise).
    FrameRenderer old_frame(48, 32);
    const SceneTexture old_scene = old_frame.upload(position_pattern(16, 8));
    old_frame.compose({{&old_scene, 1.0, {2, 3, 16, 8}, {0, 0, 48, 32}}}, 0.5);
    old_frame.replace_stimulus_region_half_rgb(first, x0, y0, width, height);
    EXPECT_NE(renderer.read_stimulus().rgba, old_frame.read_stimulus().rgba);

    EXPECT_THROW(renderer.replace_stimulus_region_half_rgb_part(second, x0, y0, width, height, {30, 12, 13, 9}),
                 DisplayError);
  }
}

TEST(FrameRendererWrites, EveryWriteToTheStimulusCountsAndReadsAndEncodesDoNot) {
  DisplayRequest request;
  request.width_px = 32;
  request.height_px = 16;
  auto display = create_display("offscreen", request);
  FrameRenderer renderer(32, 16);
  const ImageRGBA pattern = position_pattern(8, 4);
  const SceneTexture scene = renderer.upload(pattern);
  DisplaySpec spec;
  spec.peak_luminance_cd_m2 = 100.0;
  std::uint64_t count = renderer.stimulus_generation();
  const auto wrote = [&](const char* what) {
    EXPECT_EQ(renderer.stimulus_generation(), count + 1) << what;
    count = renderer.stimulus_generation();
  };
  renderer.compose({{&scene, 1.0, {2, 3, 8, 4}, {0, 0, 32, 16}}}, 0.5);
  wrote("compose");
  renderer.compose_overlay({{&scene, 1.0, {20, 3, 8, 4}, {0, 0, 32, 16}}});
  wrote("compose_overlay");
  renderer.replace_stimulus(position_pattern(32, 16));
  wrote("replace_stimulus");
  renderer.replace_stimulus_region(pattern, 4, 4);
  wrote("replace_stimulus_region");
  renderer.replace_stimulus_region_half_rgb(std::vector<std::uint16_t>(3 * 2 * 2, 0x3c00), 1, 1, 2, 2);
  wrote("replace_stimulus_region_half_rgb");
  renderer.replace_stimulus_region_half_rgb_part(std::vector<std::uint16_t>(3 * 2 * 2, 0x4000), 1, 1, 2, 2, {2, 1, 1, 2});
  wrote("replace_stimulus_region_half_rgb_part");
  (void)renderer.read_stimulus();
  renderer.encode_to_display(spec);
  (void)renderer.read_display();
  renderer.replace_stimulus_region(ImageRGBA(0, 0), 0, 0);  // nothing written
  renderer.replace_stimulus_region_half_rgb_part(std::vector<std::uint16_t>(3 * 2 * 2, 0x4000), 1, 1, 2, 2, {});
  EXPECT_EQ(renderer.stimulus_generation(), count) << "reads, encodes and empty regions write nothing";
}

// EGL that cannot start: asked for by name it is an error naming what was found; --display
// offscreen falls back to OSMesa and says why. glvnd is pointed at no vendor library, so libEGL
// offers no platform (each test runs in a process of its own, before any EGL call).
TEST(DisplayFactory, EglThatCannotStartIsAClearErrorAndOffscreenFallsBackToOsMesa) {
  ASSERT_EQ(setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/glarelab_no_vendor.json", 1), 0);
  DisplayRequest request;
  request.width_px = 64;
  request.height_px = 48;
  try {
    create_display("egl", request);
    FAIL() << "expected a DisplayError";
  } catch (const DisplayError& error) {
    EXPECT_NE(std::string(error.what()).find("EGL: no display could be opened: "), std::string::npos) << error.what();
  }
  auto display = create_display("offscreen", request);
  EXPECT_EQ(display->gl_info().platform.rfind("OSMesa (EGL did not start: EGL: no display could be opened", 0), 0u)
      << display->gl_info().platform;
  check_backend_renders_pattern(*display);
}

TEST(OffscreenBackend, MissingExtensionIsAClearError) {
  DisplayRequest request;
  request.width_px = 8;
  request.height_px = 8;
  request.required_extensions = {"GL_GLARELAB_no_such_extension"};
  try {
    create_display("offscreen", request);
    FAIL() << "expected a DisplayError";
  } catch (const DisplayError& error) {
    const std::string message = error.what();
    // Whichever backend made a context says so (OSMesa after EGL here; EGL alone where no
    // libOSMesa is installed, as on a GPU server).
    EXPECT_NE(message.find("missing OpenGL extension(s) GL_GLARELAB_no_such_extension"), std::string::npos) << message;
    EXPECT_NE(message.find("OpenGL 4."), std::string::npos) << message;  // names what was found
  }
}

TEST(OffscreenBackend, TooNewGlVersionIsAClearError) {
  DisplayRequest request;
  request.width_px = 8;
  request.height_px = 8;
  request.gl_major = 9;
  request.gl_minor = 9;
  try {
    create_display("offscreen", request);
    FAIL() << "expected a DisplayError";
  } catch (const DisplayError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("OpenGL 9.9"), std::string::npos) << message;
    EXPECT_NE(message.find("offers OpenGL"), std::string::npos) << message;
  }
}

TEST(DisplayFactory, WindowWithoutDisplayIsAClearError) {
  // The test environment clears DISPLAY for every test but the WindowBackend ones.
  ASSERT_EQ(std::getenv("DISPLAY") == nullptr || std::string(std::getenv("DISPLAY")).empty(), true);
  try {
    create_display("window", DisplayRequest{});
    FAIL() << "expected a DisplayError";
  } catch (const DisplayError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("GLFW: cannot open a window"), std::string::npos) << message;
    EXPECT_NE(message.find("--display offscreen"), std::string::npos) << message;
  }
}

TEST(DisplayFactory, UnknownKindIsAClearError) {
  EXPECT_THROW(create_display("hologram", DisplayRequest{}), DisplayError);
}

TEST(WindowBackend, RendersKnownPatternUnderX) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "WindowBackend tests run under xvfb-run (see tests/CMakeLists.txt)";
  DisplayRequest request;
  request.width_px = 64;
  request.height_px = 48;
  auto display = create_display("window", request);
  EXPECT_EQ(display->kind(), "window");
  EXPECT_TRUE(display->real_time());
  EXPECT_EQ(display->width_px(), 64);
  EXPECT_GT(display->refresh_hz(), 0.0);
  check_backend_renders_pattern(*display);
  EXPECT_TRUE(display->poll_keys().empty());
  EXPECT_FALSE(display->close_requested());
}

TEST(WindowBackend, BadMonitorIndexIsAClearError) {
  DisplayRequest request;
  request.monitor = 7;
  try {
    create_display("window", request);
    FAIL() << "expected a DisplayError";
  } catch (const DisplayError& error) {
    EXPECT_NE(std::string(error.what()).find("monitor 7 requested"), std::string::npos) << error.what();
  }
}

TEST(WindowBackend, BothBackendsInOneProcess) {
  // GL entry points are reloaded per backend; each renders correctly after the other.
  DisplayRequest request;
  request.width_px = 48;
  request.height_px = 40;
  {
    auto offscreen = create_display("offscreen", request);
    check_backend_renders_pattern(*offscreen);
  }
  {
    auto window = create_display("window", request);
    check_backend_renders_pattern(*window);
  }
  auto offscreen_again = create_display("offscreen", request);
  check_backend_renders_pattern(*offscreen_again);
}

}  // namespace
}  // namespace glarelab
