// The glare stage: control passes frames through bit-identically, a static eye gives the same
// frame at every time, a dynamic eye changes over time but is reproducible from (seed, time), the
// convolution conserves each channel's energy, and skipping glare on invisible frames costs at most
// the visibility threshold (measured against the convolution it skipped).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <cstdio>

#include "glare/eye/aperture_raster.h"
#include "glare/cpu/convolution.h"
#include "glare/eye/eye_model.h"
#include "glare/eye/eyelids.h"
#include "glare/cpu/gaze_window_convolution.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "glare/wave/spectral_psf.h"
#include "stimuli/display_model.h"
#include "runner/display/compute_context.h"
#include "glare/cpu/lit_regions.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

GlareSpec small_spec() {
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.backend = GlareBackendRequest::cpu;
  spec.grid_px = 128;  // PSF 128 px of lambda / 10 mm = 0.0033 deg: 17 display pixels across
  spec.wavelength_samples = 8;
  return spec;
}

DisplaySpec small_display() {
  DisplaySpec display;
  display.width_px = 96;
  display.height_px = 64;
  return display;
}

// A uniform surround with a bright square in the middle, far from the edges.
ImageRGBA lamp_frame(float surround_cd_m2, float lamp_cd_m2) {
  ImageRGBA frame(96, 64, surround_cd_m2);
  for (int y = 28; y < 36; ++y)
    for (int x = 44; x < 52; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp_cd_m2;
  return frame;
}

double channel_sum(const ImageRGBA& image, int channel) {
  double sum = 0.0;
  for (std::size_t i = static_cast<std::size_t>(channel); i < image.rgba.size(); i += 4) sum += image.rgba[i];
  return sum;
}

// max_x |a(x) - b(x)| / max(Y_b(x), floor) over the luminance Y.
double max_relative_change(const ImageRGBA& changed, const ImageRGBA& original, double floor_cd_m2) {
  double worst = 0.0;
  for (std::size_t i = 0; i < original.rgba.size(); i += 4) {
    const double before = luminance_rec709(original.rgba[i], original.rgba[i + 1], original.rgba[i + 2]);
    const double after = luminance_rec709(changed.rgba[i], changed.rgba[i + 1], changed.rgba[i + 2]);
    worst = std::max(worst, std::abs(after - before) / std::max(before, floor_cd_m2));
  }
  return worst;
}

TEST(GlareStage, ControlReturnsTheFrameBitIdentical) {
  GlareStage stage(small_spec(), small_display(), 7);
  ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  frame.pixel(3, 4)[1] = 1e-7f;  // values a round trip through any arithmetic would disturb
  frame.pixel(5, 6)[2] = 12345.678f;
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(frame, GlareMode::control, 1.25, &report);
  EXPECT_EQ(out.rgba, frame.rgba);
  EXPECT_FALSE(report.convolved);
}

TEST(GlareStage, StaticEyeGivesTheSameFrameAtEveryTime) {
  GlareStage stage(small_spec(), small_display(), 7);
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareFrameReport report;
  const ImageRGBA early = stage.apply(frame, GlareMode::static_eye, 0.1, &report);
  ASSERT_TRUE(report.convolved);
  const ImageRGBA late = stage.apply(frame, GlareMode::static_eye, 3.7, &report);
  EXPECT_EQ(early.rgba, late.rgba);
  EXPECT_NE(early.rgba, frame.rgba);  // and it is glare, not the frame
}

TEST(GlareStage, DynamicEyeChangesOverTimeAndIsReproducibleFromSeedAndTime) {
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareStage first(small_spec(), small_display(), 11);
  GlareStage second(small_spec(), small_display(), 11);
  const ImageRGBA a = first.apply(frame, GlareMode::dynamic, 0.5);
  const ImageRGBA b = second.apply(frame, GlareMode::dynamic, 0.5);
  EXPECT_EQ(a.rgba, b.rgba);
  const ImageRGBA later = first.apply(frame, GlareMode::dynamic, 1.5);
  EXPECT_GT(max_relative_change(later, a, 0.5), 1e-4);
  GlareStage other_seed(small_spec(), small_display(), 12);
  EXPECT_NE(other_seed.apply(frame, GlareMode::dynamic, 0.5).rgba, a.rgba);
}

TEST(GlareStage, ConvolutionConservesEachChannelsEnergyWhenNothingLeavesTheFrame) {
  GlareStage stage(small_spec(), small_display(), 3);
  const ImageRGBA frame = lamp_frame(0.0f, 500.0f);  // black surround: nothing near the edges
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(frame, GlareMode::dynamic, 0.2, &report);
  ASSERT_TRUE(report.convolved);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel_sum(out, c) / channel_sum(frame, c), 1.0, 1e-6) << "channel " << c;
  // Light spreads out of the lamp: its centre loses, the surround next to it gains.
  EXPECT_LT(out.pixel(47, 31)[1], 500.0f);
  EXPECT_GT(out.pixel(40, 31)[1], 0.0f);
}

TEST(GlareStage, VisibilityBoundHoldsAndSkippingAnInvisibleFrameCostsLessThanTheThreshold) {
  // A very dim frame (lamp 1e-4 cd/m2 on black): the skip is decided from the bound.
  GlareSpec spec = small_spec();
  GlareStage skipping(spec, small_display(), 5);
  const ImageRGBA dim = lamp_frame(0.0f, 1e-4f);
  GlareFrameReport report;
  const ImageRGBA skipped = skipping.apply(dim, GlareMode::static_eye, 0.0, &report);
  EXPECT_FALSE(report.convolved);
  EXPECT_FALSE(report.skip_reason.empty());
  EXPECT_EQ(skipped.rgba, dim.rgba);
  EXPECT_LT(report.visibility_bound, spec.visibility_weber_fraction);
  // The error of skipping: the same frame with the convolution done.
  spec.skip_invisible = false;
  GlareStage forced(spec, small_display(), 5);
  GlareFrameReport forced_report;
  const ImageRGBA glared = forced.apply(dim, GlareMode::static_eye, 0.0, &forced_report);
  ASSERT_TRUE(forced_report.convolved);
  const double error = max_relative_change(glared, dim, spec.visibility_floor_cd_m2);
  std::printf("skip error (dim frame): measured %.3g, bound %.3g, threshold %.3g, wing fraction %.3f\n", error,
              report.visibility_bound, spec.visibility_weber_fraction, report.wing_fraction);
  EXPECT_GT(error, 0.0);
  EXPECT_LE(error, report.visibility_bound * (1.0 + 1e-6));

  // A visible case: the bound still bounds the change, and the stage does not skip.
  const ImageRGBA bright = lamp_frame(1.0f, 200.0f);
  const ImageRGBA bright_glared = forced.apply(bright, GlareMode::static_eye, 0.0, &forced_report);
  const double bright_change = max_relative_change(bright_glared, bright, spec.visibility_floor_cd_m2);
  EXPECT_LE(bright_change, forced_report.visibility_bound * (1.0 + 1e-6));
  EXPECT_GT(bright_change, spec.visibility_weber_fraction);
  GlareFrameReport not_skipped;
  skipping.apply(bright, GlareMode::static_eye, 0.0, &not_skipped);
  EXPECT_TRUE(not_skipped.convolved);
}

TEST(GlareStage, FibreGratingsDropOutBehindASmallPupil) {
  // Moon and Spencer (Ritschel Eq. 2): D = 4.9 - 3 tanh(0.4 (log10 L + 1)) mm. A 2000 cd/m2 field
  // gives 2.09 mm, inside the clear lens centre (cortex annulus from 3 mm); 0.01 cd/m2 gives 6.04 mm.
  // Hippus (Eq. 1) adds at most 0.1 (9 / D) sqrt(1 - D / 9): 0.38 mm and 0.06 mm.
  GlareStage stage(small_spec(), small_display(), 9);
  GlareFrameReport bright, dark;
  stage.apply(ImageRGBA(96, 64, 2000.0f), GlareMode::static_eye, 0.0, &bright);
  stage.apply(ImageRGBA(96, 64, 0.01f), GlareMode::static_eye, 0.0, &dark);
  EXPECT_NEAR(bright.pupil_diameter_mm, 4.9 - 3.0 * std::tanh(0.4 * (std::log10(2000.0) + 1.0)), 0.38);
  EXPECT_NEAR(dark.pupil_diameter_mm, 4.9 - 3.0 * std::tanh(0.4 * (std::log10(0.01) + 1.0)), 0.07);
  EXPECT_FALSE(bright.gratings_in_pupil);
  EXPECT_TRUE(dark.gratings_in_pupil);
}

TEST(GlareStage, CroppedConvolutionEqualsTheWholeFrameConvolution) {
  // The stage convolves only the black-bordered region light can reach; the reference convolves
  // the whole frame with the same PSF.
  GlareStage stage(small_spec(), small_display(), 4);
  const ImageRGBA frame = lamp_frame(0.0f, 300.0f);
  const std::optional<Psf> psf = stage.display_psf(GlareMode::static_eye, 0.0, mean_luminance(frame));
  ASSERT_TRUE(psf.has_value());
  const ImageRGBA whole = convolve_image_cpu(frame, *psf, ConvolutionOptions{});
  const ImageRGBA cropped = stage.apply(frame, GlareMode::static_eye, 0.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < whole.rgba.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(whole.rgba[i] - cropped.rgba[i])));
  EXPECT_LT(worst, 300.0 * 1e-6);
}

// A frame's facts (its luminance range and lit boxes) are found on its first frame and kept for
// the frames after: every frame is then the frame found afresh, bit for bit; and the kept facts
// are what the stage uses (told that a lit frame has no lit boxes, it glares nothing).
TEST(GlareStage, KeptFrameFactsGiveTheFramesFoundAfresh) {
  const ImageRGBA frame = lamp_frame(0.0f, 300.0f);
  GlareStage kept_stage(small_spec(), small_display(), 4), fresh_stage(small_spec(), small_display(), 4);
  FrameFacts facts;
  for (const double time_s : {0.2, 0.25, 0.3}) {
    GlareFrameReport kept_report, fresh_report;
    const ImageRGBA kept = kept_stage.apply(frame, GlareMode::dynamic, time_s, &kept_report, std::nullopt, std::nullopt, &facts);
    const ImageRGBA fresh = fresh_stage.apply(frame, GlareMode::dynamic, time_s, &fresh_report);
    EXPECT_EQ(kept.rgba, fresh.rgba) << "t = " << time_s;
    EXPECT_TRUE(kept_report.convolved);
    EXPECT_EQ(kept_report.visibility_bound, fresh_report.visibility_bound);
    ASSERT_TRUE(facts.luminance_range_cd_m2.has_value());
    ASSERT_EQ(facts.lit_boxes.size(), 1u);
    EXPECT_EQ(facts.lit_boxes.begin()->second, lit_regions(frame, facts.lit_boxes.begin()->first));
  }
  FrameFacts dark = facts;
  dark.lit_boxes.begin()->second.clear();
  GlareFrameReport report;
  const ImageRGBA unlit = kept_stage.apply(frame, GlareMode::dynamic, 0.35, &report, std::nullopt, std::nullopt, &dark);
  EXPECT_EQ(unlit.rgba, frame.rgba) << "the kept facts are the ones used";
  ASSERT_TRUE(report.changed_boxes.has_value());
  EXPECT_TRUE(report.changed_boxes->empty());
}

double relative_l2(const ImageRGBA& test, const ImageRGBA& reference) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < reference.rgba.size(); ++k) {
    if (k % 4 == 3) continue;
    const double d = static_cast<double>(test.rgba[k]) - reference.rgba[k];
    difference += d * d;
    norm += static_cast<double>(reference.rgba[k]) * reference.rgba[k];
  }
  return std::sqrt(difference / norm);
}

// The stage's CPU result as the stage computed it before it went through the compute backend,
// spelled out here from the CPU functions: the eye's aperture rasterised, the 575 nm PSF (defocus
// phase), the chromatic blur, the display scale, then the convolution of the crop light can reach.
ImageRGBA direct_cpu_glare(const GlareSpec& spec, const DisplaySpec& display, std::uint64_t seed, const ImageRGBA& frame,
                           double time_s) {
  EyeParameters parameters;
  parameters.initial_field_luminance_cd_m2 = mean_luminance(frame);
  parameters.mode = GlareMode::static_eye;
  parameters.static_time_s = spec.static_time_s;
  const ApertureGeometry geometry = EyeModel(parameters, seed).geometry_at(time_s);
  MonochromaticPsfOptions mono;
  mono.raster.grid_px = spec.grid_px;
  mono.raster.aperture_width_mm = spec.aperture_width_mm;
  mono.raster.supersampling = spec.supersampling;
  mono.wavelength_nm = 575.0;
  mono.phase = PhaseForm::defocus;
  const MonochromaticPsfResult reference = compute_monochromatic_psf(
      rasterise_aperture(geometry, mono.raster), geometry.pupil_diameter_mm, geometry.defocus_dioptres, mono);
  SpectralPsfOptions spectral;
  spectral.wavelength_samples = spec.wavelength_samples;
  spectral.reference_wavelength_nm = 575.0;
  const Psf psf = resample_psf_to_display(spectral_psf_from_reference(reference.psf, spectral).psf,
                                          DisplayModel(display).degrees_per_pixel_at_centre());
  // The lamp frame's non-black box (44..51, 28..35) grown by the PSF's reach, inside the frame.
  const int reach = psf.size_px / 2;
  const int x0 = std::max(0, 44 - reach), y0 = std::max(0, 28 - reach);
  const int x1 = std::min(frame.width_px - 1, 51 + reach), y1 = std::min(frame.height_px - 1, 35 + reach);
  ImageRGBA crop(x1 - x0 + 1, y1 - y0 + 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) std::copy_n(frame.pixel(x, y), 4, crop.pixel(x - x0, y - y0));
  const ImageRGBA glared = convolve_image_cpu(crop, psf, ConvolutionOptions{});
  ImageRGBA out = frame;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) std::copy_n(glared.pixel(x - x0, y - y0), 4, out.pixel(x, y));
  return out;
}

TEST(GlareStage, CpuBackendGivesTheDirectCpuComputationBitForBit) {
  const GlareSpec spec = small_spec();
  GlareStage stage(spec, small_display(), 4);
  EXPECT_NE(stage.backend_reason().find("cpu float64"), std::string::npos) << stage.backend_reason();
  const ImageRGBA frame = lamp_frame(0.0f, 300.0f);
  GlareFrameReport report;
  const ImageRGBA out = stage.apply(frame, GlareMode::static_eye, 0.0, &report);
  ASSERT_TRUE(report.convolved);
  EXPECT_EQ(out.rgba, direct_cpu_glare(spec, small_display(), 4, frame, 0.0).rgba);
}

// "auto" without a GL context takes the CPU and its planned float32 path for the frames
// (glare/cpu/float_glare.h): within 1e-6 relative L2 of the float64 reference ("cpu") on static and
// dynamic frames, and a second frame of the same scene reuses its spectrum with the same result.
TEST(GlareStage, AutoOnTheCpuTakesThePlannedFloatPathWithinOneMillionthOfTheReference) {
  GlareSpec reference_spec = small_spec();
  reference_spec.grid_px = 256;
  reference_spec.wavelength_samples = 32;
  reference_spec.skip_invisible = false;
  GlareSpec planned_spec = reference_spec;
  planned_spec.backend = GlareBackendRequest::automatic;
  GlareStage reference(reference_spec, small_display(), 4);
  GlareStage planned(planned_spec, small_display(), 4);  // no GL context factory: the CPU
  EXPECT_EQ(planned.backend_reason().rfind("glare backend auto picked cpu float32 planned: ", 0), 0u)
      << planned.backend_reason();
  const ImageRGBA frame = lamp_frame(0.5f, 3000.0f);
  for (const auto& [mode, time_s] : {std::pair{GlareMode::static_eye, 0.0}, std::pair{GlareMode::dynamic, 2.0},
                                     std::pair{GlareMode::dynamic, 2.0 + 1.0 / 60.0}}) {
    GlareFrameReport report;
    const ImageRGBA expected = reference.apply(frame, mode, time_s);
    const ImageRGBA got = planned.apply(frame, mode, time_s, &report);
    ASSERT_TRUE(report.convolved) << report.skip_reason;
    const double error = relative_l2(got, expected);
    EXPECT_LT(error, 1e-6) << to_string(mode) << " at " << time_s << " s";
    std::cout << to_string(mode) << " at " << time_s << " s: relative L2 " << error << "\n";
  }
}

// The demo's session frame: 1024 x 512, two 256 px dim rooms (0.5 cd/m2) each with a 100 cd/m2
// lamp, on black.
ImageRGBA demo_frame() {
  ImageRGBA frame(1024, 512, 0.0f);
  for (const int left : {128, 640})
    for (int y = 128; y < 384; ++y)
      for (int x = left; x < left + 256; ++x) {
        const bool lamp = std::abs(x - (left + 128)) < 6 && std::abs(y - 200) < 6;
        for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp ? 100.0f : 0.5f;
      }
  return frame;
}

TEST(GlareStage, RoomsConvolvedApartEqualTheWholeFrameConvolution) {
  // The stage convolves each lit region on its own (glare/cpu/lit_regions.h); the reference convolves
  // the whole 1024 x 512 frame at once in float64 with the same display PSF.
  DisplaySpec display;
  display.width_px = 1024;
  display.height_px = 512;
  const ImageRGBA frame = demo_frame();
  for (const GlareBackendRequest backend : {GlareBackendRequest::cpu, GlareBackendRequest::automatic}) {
    GlareSpec spec;
    spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
    spec.backend = backend;
    spec.wavelength_samples = 16;
    spec.skip_invisible = false;
    GlareStage stage(spec, display, 3);
    const double mean_cd_m2 = mean_luminance(frame);
    const std::optional<Psf> psf = stage.display_psf(GlareMode::dynamic, 1.5, mean_cd_m2);
    ASSERT_TRUE(psf.has_value());
    const ImageRGBA reference = convolve_image_cpu(frame, *psf, ConvolutionOptions{});
    GlareStage fresh(spec, display, 3);  // the same eye, at the same time
    GlareFrameReport report;
    const ImageRGBA got = fresh.apply(frame, GlareMode::dynamic, 1.5, &report, std::nullopt, mean_cd_m2);
    ASSERT_TRUE(report.convolved) << report.skip_reason;
    const double error = relative_l2(got, reference);
    // float64: only the rounding of other FFT sizes; the planned float32 path: its frame budget.
    EXPECT_LT(error, backend == GlareBackendRequest::cpu ? 1e-12 : 1e-6) << spelling(backend);
    std::printf("%s: rooms apart vs whole frame, relative L2 %.3g\n", std::string(spelling(backend)).c_str(), error);
    EXPECT_EQ(got.pixel(512, 256)[1], 0.0f) << "between the rooms, beyond the PSF's reach";
    EXPECT_GT(got.pixel(128 - 5, 200)[1], 0.0f) << "glare spills past a room's edge";
  }
}

TEST(GlareStage, GlBackendAgreesWithTheCpuBackendOnASessionFrame) {
  // Small grid and frame: the GL path runs on llvmpipe here.
  GlareSpec spec = small_spec();
  GlareStage cpu(spec, small_display(), 21);
  spec.backend = GlareBackendRequest::gl;
  GlareStage gl(spec, small_display(), 21, gl::compute_context_factory());
  EXPECT_NE(gl.backend_reason().find("glare backend gl"), std::string::npos) << gl.backend_reason();
  ImageRGBA frame = lamp_frame(0.5f, 2000.0f);
  frame.pixel(10, 10)[0] = 50.0f;
  for (const GlareMode mode : {GlareMode::static_eye, GlareMode::dynamic}) {
    GlareFrameReport cpu_report, gl_report;
    const ImageRGBA a = cpu.apply(frame, mode, 0.75, &cpu_report);
    const ImageRGBA b = gl.apply(frame, mode, 0.75, &gl_report);
    ASSERT_TRUE(cpu_report.convolved && gl_report.convolved);
    const double error = relative_l2(b, a);
    std::printf("session frame, %s eye, GL vs CPU double: relative L2 %.3g\n", to_string(mode).c_str(), error);
    EXPECT_LT(error, 1e-3);
    EXPECT_GT(relative_l2(a, frame), 1e-3) << "and both are glare, not the frame";
  }
}

TEST(GlareStage, GazeWindowEqualsTheGazeWindowConvolutionAndCentresWithoutGaze) {
  GlareSpec spec = small_spec();
  spec.gaze_window_px = 32;
  GlareStage stage(spec, small_display(), 4);
  const ImageRGBA frame = lamp_frame(0.2f, 300.0f);
  const std::optional<Psf> psf = stage.display_psf(GlareMode::static_eye, 0.0, mean_luminance(frame));
  ASSERT_TRUE(psf.has_value());
  GazeWindowOptions options;
  options.window_px = 32;
  GlareFrameReport report;
  const ImageRGBA windowed = stage.apply(frame, GlareMode::static_eye, 0.0, &report, GazePoint{0.45, 0.4});
  ASSERT_TRUE(report.window.has_value());
  EXPECT_EQ(report.window->width_px, 32);
  EXPECT_EQ(report.window->x0_px, static_cast<int>(std::lround(0.45 * 96 - 16)));
  EXPECT_EQ(report.window->y0_px, static_cast<int>(std::lround(0.4 * 64 - 16)));
  const ImageRGBA reference = convolve_image_gaze_window_cpu(frame, *psf, 0.45, 0.4, options);
  EXPECT_LT(relative_l2(windowed, reference), 1e-7);
  // Outside the window the frame is untouched.
  EXPECT_EQ(windowed.pixel(2, 2)[1], frame.pixel(2, 2)[1]);
  // No gaze: the window sits on the display centre.
  const ImageRGBA centred = stage.apply(frame, GlareMode::static_eye, 0.0, &report);
  EXPECT_EQ(report.window->x0_px, 48 - 16);
  EXPECT_EQ(report.window->y0_px, 32 - 16);
  EXPECT_LT(relative_l2(centred, convolve_image_gaze_window_cpu(frame, *psf, 0.5, 0.5, options)), 1e-7);
}

TEST(GlareStage, GazeWindowInADemoSizedSessionFrameIsExactInsideAndCheaper) {
  // The demo's frame: 1024 x 512, two 256 px dim rooms (0.5 cd/m2) each with a 100 cd/m2 lamp, on
  // black; grid 256 over 10 mm (a 35 px PSF). Window 256 px around a gaze on the left lamp.
  DisplaySpec display;
  display.width_px = 1024;
  display.height_px = 512;
  ImageRGBA frame(1024, 512, 0.0f);
  for (const int left : {128, 640})
    for (int y = 128; y < 384; ++y)
      for (int x = left; x < left + 256; ++x) {
        const bool lamp = std::abs(x - (left + 128)) < 6 && std::abs(y - 200) < 6;
        for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = lamp ? 100.0f : 0.5f;
      }
  GlareSpec spec;
  spec.model = GlareModel::ritschel;  // the wave-optics eye alone, whose behaviour these checks state
  spec.backend = GlareBackendRequest::cpu;
  spec.wavelength_samples = 16;
  GlareStage full(spec, display, 2);
  spec.gaze_window_px = 256;
  GlareStage windowed(spec, display, 2);
  const GazePoint gaze{256.0 / 1024.0, 200.0 / 512.0};
  full.apply(frame, GlareMode::static_eye, 0.0);  // PSFs computed and cached: only convolutions timed
  windowed.apply(frame, GlareMode::static_eye, 0.0, nullptr, gaze);
  const auto time_ms = [](auto&& run) {
    const auto start = std::chrono::steady_clock::now();
    run();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  ImageRGBA reference, window_frame;
  GlareFrameReport report;
  const double full_ms = time_ms([&] { reference = full.apply(frame, GlareMode::static_eye, 0.0); });
  const double window_ms = time_ms([&] { window_frame = windowed.apply(frame, GlareMode::static_eye, 0.0, &report, gaze); });
  ASSERT_TRUE(report.window.has_value());
  // Inside the window before blending the result is the full-frame convolution: with the blend
  // weight w, window - frame = w (full - frame) at every window pixel.
  double worst_inside = 0.0, outside_error = 0.0, outside_norm = 0.0;
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 1024; ++x)
      for (int c = 0; c < 3; ++c) {
        const double original = frame.pixel(x, y)[c], full_value = reference.pixel(x, y)[c];
        const double value = window_frame.pixel(x, y)[c];
        if (report.window->contains(x, y)) {
          const double w = gaze_blend_weight(*report.window, x, y);
          worst_inside = std::max(worst_inside, std::abs(value - (original + w * (full_value - original))) /
                                                    std::max(full_value, 1e-3));
        }
        outside_error += (value - full_value) * (value - full_value);
        outside_norm += full_value * full_value;
      }
  std::printf("gaze window 256 in a 1024 x 512 demo frame: %.1f ms against %.1f ms full frame; relative error in the "
              "window %.2g, whole-frame relative L2 against full-frame glare %.3g\n",
              window_ms, full_ms, worst_inside, std::sqrt(outside_error / outside_norm));
  EXPECT_LT(worst_inside, 1e-5);
}

TEST(GlareStage, MeasuredPupilReplacesTheModelPupilOfTheDynamicEye) {
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareStage model(small_spec(), small_display(), 8);
  GlareStage measured(small_spec(), small_display(), 8);
  measured.record_measured_pupil(0.0, 6.5);
  measured.record_measured_pupil(1.0, 12.0);  // beyond the model's range: held at its 9 mm
  GlareFrameReport a, b, late;
  const ImageRGBA model_frame = model.apply(frame, GlareMode::dynamic, 0.5, &a);
  const ImageRGBA measured_frame = measured.apply(frame, GlareMode::dynamic, 0.5, &b);
  EXPECT_LT(a.pupil_diameter_mm, 5.0);  // Eq. 2 at about 3 cd/m2: 3.4 mm
  EXPECT_EQ(b.pupil_diameter_mm, 6.5);
  EXPECT_GT(relative_l2(measured_frame, model_frame), 1e-3);
  measured.apply(frame, GlareMode::dynamic, 1.5, &late);
  EXPECT_EQ(late.pupil_diameter_mm, 9.0);
  // A static eye stays frozen whatever is measured.
  GlareFrameReport frozen;
  measured.apply(frame, GlareMode::static_eye, 0.5, &frozen);
  model.apply(frame, GlareMode::static_eye, 0.5, &a);
  EXPECT_EQ(frozen.pupil_diameter_mm, a.pupil_diameter_mm);
}

TEST(GlareStage, DetectedBlinksDriveTheLidsInsteadOfTheSchedule) {
  // The schedule's first blink for seed 6, and a detected blink at another time.
  const EyelidModel lids(EyeParameters{}, 6);
  const EyeParameters eye;
  const double scheduled_s = lids.blink_onset_s(1) + eye.blink_closing_duration_s + 0.5 * eye.blink_closed_duration_s;
  const double detected_onset_s = lids.blink_onset_s(1) + 1.0;
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  GlareStage own(small_spec(), small_display(), 6);
  GlareFrameReport report;
  own.apply(frame, GlareMode::dynamic, scheduled_s - 0.5, &report);
  own.apply(frame, GlareMode::dynamic, scheduled_s, &report);
  EXPECT_TRUE(report.eye_closed) << "the model's own blink closes the eye";
  GlareStage driven(small_spec(), small_display(), 6);
  driven.set_detected_blinks({{detected_onset_s, detected_onset_s + 0.15}});
  driven.apply(frame, GlareMode::dynamic, scheduled_s - 0.5, &report);
  driven.apply(frame, GlareMode::dynamic, scheduled_s, &report);
  EXPECT_FALSE(report.eye_closed) << "the schedule no longer blinks";
  // Closing 100 ms from the detected onset, closed until the offset, then 200 ms opening.
  driven.apply(frame, GlareMode::dynamic, detected_onset_s + 0.12, &report);
  EXPECT_TRUE(report.eye_closed);
  EXPECT_TRUE(report.convolved) << "a dynamic eye holds the PSF of its last open frame";
  driven.apply(frame, GlareMode::dynamic, detected_onset_s + 0.15 + 0.25, &report);
  EXPECT_FALSE(report.eye_closed);
  // A blink still open (no offset yet) keeps the lids closed.
  driven.set_detected_blinks({{detected_onset_s, detected_onset_s + 0.15}, {detected_onset_s + 2.0, INFINITY}});
  driven.apply(frame, GlareMode::dynamic, detected_onset_s + 3.5, &report);
  EXPECT_TRUE(report.eye_closed);
}

// A preview (glarelab render) passes the frames before the one it shows with record_dynamic_frame,
// computing no PSF; when the shown frame falls in a blink it must hold the PSF of the last open
// frame passed, exactly as the session that computed every frame does.
TEST(GlareStage, AFramePassedByGivesTheHeldPsfOfTheSessionThatComputedIt) {
  const EyelidModel lids(EyeParameters{}, 6);
  const EyeParameters eye;
  const double closed_s = lids.blink_onset_s(1) + eye.blink_closing_duration_s + 0.5 * eye.blink_closed_duration_s;
  const ImageRGBA frame = lamp_frame(0.5f, 200.0f);
  // Frames every 1/60 s up to the closed one: the last ones before it are already closing.
  std::vector<double> times;
  for (double t = closed_s - 0.5; t < closed_s - 1e-9; t += 1.0 / 60.0) times.push_back(t);
  GlareStage session(small_spec(), small_display(), 6), preview(small_spec(), small_display(), 6),
      forgetful(small_spec(), small_display(), 6);
  int closed_before = 0;
  for (const double t : times) {
    GlareFrameReport report;
    session.apply(frame, GlareMode::dynamic, t, &report);
    closed_before += report.eye_closed ? 1 : 0;
    preview.record_dynamic_frame(t, mean_luminance(frame));
  }
  ASSERT_GT(closed_before, 0) << "the case needs closed frames before the shown one, so the held PSF is an older frame's";
  ASSERT_LT(closed_before, static_cast<int>(times.size()));
  GlareFrameReport from_session, from_preview, from_nothing;
  const ImageRGBA expected = session.apply(frame, GlareMode::dynamic, closed_s, &from_session);
  const ImageRGBA shown = preview.apply(frame, GlareMode::dynamic, closed_s, &from_preview);
  ASSERT_TRUE(from_session.eye_closed && from_session.convolved);
  EXPECT_TRUE(from_preview.eye_closed && from_preview.convolved);
  EXPECT_EQ(shown.rgba, expected.rgba) << "bit for bit";
  // Without the frames before, no open frame came first: nothing to hold (the glare is skipped).
  forgetful.apply(frame, GlareMode::dynamic, closed_s, &from_nothing);
  EXPECT_FALSE(from_nothing.convolved);
}

TEST(GlareStage, VisibilityBoundFormula) {
  // Spelled out: peak 100, wing 0.2 -> 20 cd/m2 of veil at most; against 10 cd/m2 -> 2.
  EXPECT_DOUBLE_EQ(visibility_bound(100.0, 10.0, 0.2, 0.01), 2.0);
  // Below the floor the floor is the reference.
  EXPECT_DOUBLE_EQ(visibility_bound(1.0, 0.0, 0.1, 0.5), 0.2);
}

}  // namespace
}  // namespace glarelab

