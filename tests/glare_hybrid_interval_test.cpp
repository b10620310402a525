// The hybrid and human eyes' frames of a dynamic interval (stimuli/glare_stage_hybrid.cpp): the far
// glare, the halo's ring, the energies and the lit boxes kept for the composed frame while it comes
// again, and the near part's rows finished (far and halo added, back to luminance) as the planned
// path's inverse transform writes them. The reference for each is the computation without what is
// kept: a stage that has seen nothing before, and the backends' generic convolve_regions followed
// by the same finish in a separate pass.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "glare/cpu/float_glare.h"
#include "glare/cpu/lit_regions.h"
#include "glare/cpu/psf.h"
#include "stimuli/display_model.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

bool same_bits(const ImageRGBA& a, const ImageRGBA& b) {
  return a.width_px == b.width_px && a.height_px == b.height_px && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

// A dim room with two lamps apart and a black band, so that the lit boxes leave part of the frame
// unreached (the finish runs there on the frame's own pixels).
ImageRGBA room(int width, int height) {
  ImageRGBA frame(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width / 2; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 0.5f + 0.01f * static_cast<float>((x + 3 * y + c) % 7);
  for (int y = 20; y < 23; ++y)
    for (int x = 30; x < 33; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 8000.0f;
  for (int y = 40; y < 42; ++y)
    for (int x = 150; x < 152; ++x) frame.pixel(x, y)[1] = 3000.0f;
  return frame;
}

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 192;
  display.height_px = 96;
  return display;
}

// The planned path of the fused-finish tests: a 128 grid, 8 wavelengths, at the display's scale.
CpuFloatGlareSettings small_planned_settings(const DisplaySpec& display) {
  CpuFloatGlareSettings settings;
  settings.grid_px = 128;
  settings.wavelength_samples = 8;
  settings.display_degrees_per_pixel = DisplayModel(display).degrees_per_pixel_at_centre();
  return settings;
}

ApertureGeometry four_mm_pupil() {
  ApertureGeometry geometry;
  geometry.pupil_diameter_mm = 4.0;
  return geometry;
}

// Frames of a dynamic interval (one composed frame, the eye moving) on the planned path, with the
// frame's facts as a session keeps them, equal bit for bit to each frame computed by a stage that
// has kept nothing: the eye's history given by record_dynamic_frame, as a preview gives it.
TEST(HybridInterval, KeptFramesOfAnIntervalEqualFramesComputedAfresh) {
  const DisplaySpec display = small_display();
  const ImageRGBA frame = room(display.width_px, display.height_px);
  const double field = mean_luminance(frame);
  for (GlareModel model : {GlareModel::human, GlareModel::hybrid}) {
    GlareSpec spec;
    spec.model = model;
    spec.grid_px = 128;
    spec.wavelength_samples = 8;
    GlareStage kept(spec, display, 7);
    FrameFacts facts;
    for (int k = 0; k < 4; ++k) {
      const double time_s = 0.5 + k / 60.0;
      GlareFrameReport report;
      const ImageRGBA glared = kept.apply(frame, GlareMode::dynamic, time_s, &report, std::nullopt, field, &facts);
      ASSERT_TRUE(report.convolved);
      if (model == GlareModel::human) {
        EXPECT_GT(report.halo_energy, 0.0);  // the dark room opens the pupil
      }
      GlareStage fresh(spec, display, 7);
      for (int j = 0; j < k; ++j) fresh.record_dynamic_frame(0.5 + j / 60.0, field);
      const ImageRGBA copy = frame;  // another image with the same pixels: compared, not named
      const ImageRGBA expected = fresh.apply(copy, GlareMode::dynamic, time_s, nullptr, std::nullopt, field);
      EXPECT_TRUE(same_bits(glared, expected)) << to_string(model) << " frame " << k;
    }
    EXPECT_NE(facts.glare_source_token, 0u);
    // One far convolution for the whole interval.
    EXPECT_EQ(kept.analytic_for(model, display.width_px, display.height_px).convolutions_computed(), 1);
  }
}

// A composed frame that changes within the interval is glared as a new frame (not the kept one).
TEST(HybridInterval, AChangedFrameIsNotTakenForTheKeptOne) {
  const DisplaySpec display = small_display();
  ImageRGBA frame = room(display.width_px, display.height_px);
  const double field = mean_luminance(frame);
  GlareSpec spec;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  GlareStage stage(spec, display, 3), other(spec, display, 3);
  const ImageRGBA first = stage.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field);
  frame.pixel(100, 10)[0] = 2000.0f;  // the same object, other pixels, no facts
  const ImageRGBA second = stage.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field);
  const ImageRGBA expected = other.apply(frame, GlareMode::static_eye, 0.0, nullptr, std::nullopt, field);
  EXPECT_FALSE(same_bits(first, second));
  EXPECT_TRUE(same_bits(second, expected));
}

// The planned path's fused finish equals the generic one (convolve_regions on a copy of the frame,
// then the finish over every row), bit for bit, with and without a frame token, on boxes that leave
// part of the frame unreached.
TEST(HybridInterval, FusedFinishEqualsTheGenericPass) {
  const DisplaySpec display = small_display();
  const ImageRGBA frame = room(display.width_px, display.height_px);
  CpuFloatGlare planned(small_planned_settings(display));
  const Psf psf = planned.display_psf(four_mm_pupil());
  const std::vector<PixelRect> boxes = lit_regions(frame, psf.size_px);
  ASSERT_GE(boxes.size(), 1u);
  // Anything per pixel that depends on the pixel's place and values: x, y and the value itself.
  const RowFinish finish = [](int y, int x_from, int x_to, float* rgba) {
    for (int x = x_from; x < x_to; ++x, rgba += 4)
      for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * 1.5f + static_cast<float>(x + 1000 * y + c) * 1e-3f;
  };
  ImageRGBA generic, fused, again;
  planned.GlareBackend::convolve_regions_finished(frame, boxes, psf, generic, finish);
  planned.convolve_regions_finished(frame, boxes, psf, fused, finish, 41);
  planned.convolve_regions_finished(frame, boxes, psf, again, finish, 41);  // the kept spectrum, named
  EXPECT_TRUE(planned.reused_scene());
  EXPECT_TRUE(same_bits(generic, fused));
  EXPECT_TRUE(same_bits(generic, again));
  bool unreached = false;  // the finish ran on the frame's own pixels too
  for (int x = 0; x < frame.width_px && !unreached; ++x) unreached = frame.pixel(x, 80)[0] == 0.0f && fused.pixel(x, 80)[0] != 0.0f;
  EXPECT_TRUE(unreached);
}

// Added to another image (the hybrid eye's kept far glare): the fused pass, the generic one and the
// sum written out (that image plus the plain convolution, pixel by pixel, then the finish), bit for
// bit; alpha is that image's.
TEST(HybridInterval, FusedFinishAddedToAnImageEqualsTheSum) {
  const DisplaySpec display = small_display();
  const ImageRGBA frame = room(display.width_px, display.height_px);
  CpuFloatGlare planned(small_planned_settings(display));
  const Psf psf = planned.display_psf(four_mm_pupil());
  const std::vector<PixelRect> boxes = lit_regions(frame, psf.size_px);
  ImageRGBA base(display.width_px, display.height_px);
  for (int y = 0; y < base.height_px; ++y)
    for (int x = 0; x < base.width_px; ++x)
      for (int c = 0; c < 4; ++c) base.pixel(x, y)[c] = 0.25f + static_cast<float>((x * 7 + y * 3 + c) % 11) * 0.125f;
  const RowFinish finish = [](int y, int x_from, int x_to, float* rgba) {
    for (int x = x_from; x < x_to; ++x, rgba += 4)
      for (int c = 0; c < 3; ++c) rgba[c] = rgba[c] * 1.5f + static_cast<float>(x + 1000 * y + c) * 1e-3f;
  };
  ImageRGBA convolved = frame;
  planned.convolve_regions(frame, boxes, psf, convolved);
  ImageRGBA expected = base;
  for (std::size_t i = 0; i < expected.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) expected.rgba[i + c] += convolved.rgba[i + c];
  for (int y = 0; y < expected.height_px; ++y) finish(y, 0, expected.width_px, expected.pixel(0, y));
  ImageRGBA generic, fused, again;
  planned.GlareBackend::convolve_regions_finished(frame, boxes, psf, generic, finish, 0, &base);
  planned.convolve_regions_finished(frame, boxes, psf, fused, finish, 43, &base);
  planned.convolve_regions_finished(frame, boxes, psf, again, finish, 43, &base);
  EXPECT_TRUE(same_bits(expected, generic));
  EXPECT_TRUE(same_bits(expected, fused));
  EXPECT_TRUE(same_bits(expected, again));
  EXPECT_EQ(fused.pixel(5, 5)[3], base.pixel(5, 5)[3]);
  // Not the frame's size: refused.
  const ImageRGBA small(10, 10);
  EXPECT_THROW(planned.convolve_regions_finished(frame, boxes, psf, fused, finish, 43, &small), std::invalid_argument);
}

}  // namespace
}  // namespace glarelab
