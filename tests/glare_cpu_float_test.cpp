// The planned float32 CPU path (glare/cpu_float_*.h) against the float64 reference path: the
// aperture bit for bit, the PSF, the spectral PSF at the display scale, the convolution and the
// whole frame to 1e-6 (relative L2), on the eye model's apertures. No timing here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "glare/eye/aperture_raster.h"
#include "glare/cpu/convolution.h"
#include "glare/cpu/float_convolution.h"
#include "glare/cpu/float_glare.h"
#include "glare/cpu/lit_regions.h"
#include "glare/cpu/float_psf.h"
#include "glare/cpu/float_spectral_psf.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/fftw_floor.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "glare/wave/spectral_psf.h"
#include "tests/aperture_rule.h"
#include "tests/glare_psf_test_support.h"

namespace glarelab {
namespace {

constexpr double kWidthMm = 10.0;

template <typename A, typename B>
double relative_l2(const A& test, const B& reference) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const double d = static_cast<double>(test[k]) - static_cast<double>(reference[k]);
    difference += d * d;
    norm += static_cast<double>(reference[k]) * static_cast<double>(reference[k]);
  }
  return std::sqrt(difference / norm);
}

ApertureGeometry eye_at(double time_s) {
  const EyeModel eye(EyeParameters{}, 1);
  while (eye.state_at(time_s).blink_closure > 0.0) time_s += 0.1;
  return eye.geometry_at(time_s);
}

TEST(GlareCpuFloat, RasteriserShortcutsAndThreadsGiveTheRuleBitForBit) {
  for (double time_s : {1.2, 7.5}) {
    ApertureGeometry geometry = eye_at(time_s);
    for (double pupil_mm : {geometry.pupil_diameter_mm, 12.0}) {  // 12 mm: wider than the grid
      geometry.pupil_diameter_mm = pupil_mm;
      const std::vector<double> rule = test::rasterise_by_the_rule(geometry, 64, kWidthMm, 2);
      for (int threads : {1, 2, 3}) {
        ApertureRasterOptions options;
        options.grid_px = 64;
        options.aperture_width_mm = kWidthMm;
        options.threads = threads;
        const ApertureGrid grid = rasterise_aperture(geometry, options);
        ASSERT_EQ(grid.transmittance.size(), rule.size());
        for (std::size_t k = 0; k < rule.size(); ++k)
          ASSERT_EQ(grid.transmittance[k], rule[k]) << "pixel " << k << ", pupil " << pupil_mm << " mm, " << threads << " threads";
      }
    }
  }
}

struct DoubleFrame {
  Psf mono, display_spectral;
  ImageRGBA frame;
};

ImageRGBA hdr_frame(int n) {
  ImageRGBA image(n, n * 3 / 4, 0.0f);
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      float* p = image.pixel(x, y);
      p[0] = 1.0f + static_cast<float>(x) / static_cast<float>(n);
      p[1] = 1.5f;
      p[2] = 1.0f + static_cast<float>(y) / static_cast<float>(n);
      p[3] = 0.25f;
    }
  for (int y = n / 4; y < n / 4 + 2; ++y)
    for (int x = n / 2; x < n / 2 + 2; ++x) image.pixel(x, y)[0] = image.pixel(x, y)[1] = image.pixel(x, y)[2] = 1e5f;
  return image;
}

DoubleFrame double_frame(const ApertureGeometry& geometry, int n, const ImageRGBA& image) {
  DoubleFrame reference;
  MonochromaticPsfOptions mono;
  mono.raster.grid_px = n;
  mono.raster.aperture_width_mm = kWidthMm;
  reference.mono = compute_monochromatic_psf(geometry, mono).psf;
  const Psf spectral = spectral_psf_from_reference(reference.mono, SpectralPsfOptions{}).psf;
  reference.display_spectral = resample_psf_to_display(spectral, 4.0 * reference.mono.degrees_per_pixel);
  reference.frame = convolve_image_cpu(image, reference.display_spectral, ConvolutionOptions{});
  return reference;
}

std::vector<float> rgb_of(const ImageRGBA& image) {
  std::vector<float> values;
  for (std::size_t k = 0; k < image.rgba.size(); ++k)
    if (k % 4 != 3) values.push_back(image.rgba[k]);
  return values;
}

TEST(GlareCpuFloat, WholeFrameWithin1e6OfTheDoublePathAtNewEyeTimes) {
  for (int n : {256, 512}) {
    CpuFloatPsfSettings psf_settings;
    psf_settings.raster.grid_px = n;
    psf_settings.raster.aperture_width_mm = kWidthMm;
    CpuFloatPsf psf(psf_settings);
    CpuFloatSpectralSettings spectral_settings;
    spectral_settings.grid_px = n;
    spectral_settings.psf_degrees_per_pixel = psf.degrees_per_pixel();
    spectral_settings.display_degrees_per_pixel = 4.0 * psf.degrees_per_pixel();
    spectral_settings.aperture_width_mm = kWidthMm;
    CpuFloatSpectralPsf spectral(spectral_settings);
    const ImageRGBA image = hdr_frame(n);
    CpuFloatConvolution convolution(image.width_px, image.height_px, spectral.display_size_px());
    convolution.set_scene(image);  // a static scene: its spectrum serves every frame below
    ImageRGBA out;
    for (double time_s : {1.2, 3.4, 9.9}) {
      const ApertureGeometry geometry = eye_at(time_s);
      const DoubleFrame reference = double_frame(geometry, n, image);
      psf.rasterise(geometry);
      psf.transform(geometry.pupil_diameter_mm, geometry.defocus_dioptres);
      const Psf mono = psf.monochromatic_psf();
      EXPECT_LT(relative_l2(mono.values, reference.mono.values), 1e-6) << n << " at " << time_s << " s";
      EXPECT_DOUBLE_EQ(mono.degrees_per_pixel, reference.mono.degrees_per_pixel);
      const Psf kernel = spectral.compute(psf.power_column_major(), geometry.pupil_diameter_mm);
      ASSERT_EQ(kernel.size_px, reference.display_spectral.size_px);
      EXPECT_LT(relative_l2(kernel.values, reference.display_spectral.values), 2e-6) << n << " at " << time_s << " s";
      convolution.convolve(kernel, out);
      EXPECT_LT(relative_l2(rgb_of(out), rgb_of(reference.frame)), 1e-6) << n << " at " << time_s << " s";
      EXPECT_EQ(out.pixel(3, 5)[3], 0.25f);  // alpha passes through
    }
  }
}

TEST(GlareCpuFloat, SpectralPsfAtCoarseDisplayPixels) {
  // Display pixels 20 PSF pixels wide (a fine grid on a coarse display).
  const ApertureGeometry geometry = eye_at(1.2);
  MonochromaticPsfOptions mono;
  mono.raster.grid_px = 256;
  mono.raster.aperture_width_mm = kWidthMm;
  const Psf reference_mono = compute_monochromatic_psf(geometry, mono).psf;
  const double display = 20.0 * reference_mono.degrees_per_pixel;
  const Psf reference =
      resample_psf_to_display(spectral_psf_from_reference(reference_mono, SpectralPsfOptions{}).psf, display);
  CpuFloatSpectralSettings settings;
  settings.grid_px = 256;
  settings.psf_degrees_per_pixel = reference_mono.degrees_per_pixel;
  settings.display_degrees_per_pixel = display;
  settings.aperture_width_mm = kWidthMm;
  CpuFloatSpectralPsf spectral(settings);
  // Column-major, as CpuFloatPsf hands it over; the PSF is not symmetric (eyelashes, particles), so a
  // layout mistake would show.
  std::vector<float> power(reference_mono.values.size());
  for (int x = 0; x < 256; ++x)
    for (int y = 0; y < 256; ++y) power[static_cast<std::size_t>(x) * 256 + y] = static_cast<float>(reference_mono.at(0, x, y));
  const Psf kernel = spectral.compute(power.data(), geometry.pupil_diameter_mm);
  ASSERT_EQ(kernel.size_px, reference.size_px);
  EXPECT_LT(relative_l2(kernel.values, reference.values), 1e-6);
}

TEST(GlareCpuFloat, SpectralPsfIsTheSameBitsOnOneTwoOrThreeThreads) {
  // The display rows are shared among the threads in tiles, each display pixel's sums taken over the
  // wavelengths in one order whichever thread runs its tile, and the refinement runs per display
  // row: the thread count must not change a bit (a frame must not depend on the computer's cores).
  const ApertureGeometry geometry = eye_at(3.4);
  CpuFloatPsfSettings psf_settings;
  psf_settings.raster.grid_px = 256;
  psf_settings.raster.aperture_width_mm = kWidthMm;
  CpuFloatPsf psf(psf_settings);
  psf.rasterise(geometry);
  psf.transform(geometry.pupil_diameter_mm, geometry.defocus_dioptres);
  std::vector<Psf> kernels;
  std::vector<int> refined;
  for (int threads : {1, 2, 3}) {
    CpuFloatSpectralSettings settings;
    settings.grid_px = 256;
    settings.psf_degrees_per_pixel = psf.degrees_per_pixel();
    settings.display_degrees_per_pixel = 4.0 * psf.degrees_per_pixel();
    settings.aperture_width_mm = kWidthMm;
    settings.threads = threads;
    CpuFloatSpectralPsf spectral(settings);
    kernels.push_back(spectral.compute(psf.power_column_major(), geometry.pupil_diameter_mm));
    refined.push_back(spectral.refined_pixels());
  }
  EXPECT_GT(refined.front(), 0);  // the refinement ran
  for (std::size_t k = 1; k < kernels.size(); ++k) {
    EXPECT_EQ(refined[k], refined.front());
    ASSERT_EQ(kernels[k].values.size(), kernels.front().values.size());
    for (std::size_t v = 0; v < kernels.front().values.size(); ++v)
      ASSERT_EQ(kernels[k].values[v], kernels.front().values[v]) << "value " << v << ", " << k + 1 << " threads";
  }
}

TEST(GlareCpuFloat, NewSceneReplacesTheKeptSpectrumAndBadImagesAreRefused) {
  ImageRGBA first = hdr_frame(64), second = hdr_frame(64);
  for (float& v : second.rgba) v *= 2.0f;
  Psf psf;
  psf.size_px = 8;
  psf.channels = 1;
  psf.values.assign(64, 1.0 / 64.0);
  CpuFloatConvolution convolution(64, 48, 8);
  EXPECT_THROW(convolution.convolve(psf, first), std::logic_error);
  convolution.set_scene(first);
  ImageRGBA out_first, out_second;
  convolution.convolve(psf, out_first);
  convolution.set_scene(second);
  convolution.convolve(psf, out_second);
  const ImageRGBA expected = convolve_image_cpu(second, psf, ConvolutionOptions{});
  EXPECT_LT(relative_l2(rgb_of(out_second), rgb_of(expected)), 1e-6);
  EXPECT_NEAR(out_second.pixel(10, 10)[1], 2.0f * out_first.pixel(10, 10)[1], 1e-4f);
  // Alpha and depth come from the scene.
  for (std::size_t k = 3; k < second.rgba.size(); k += 4) EXPECT_EQ(out_second.rgba[k], second.rgba[k]);
  // A refused scene leaves the last one: its spectrum, alpha and depth.
  ImageRGBA refused = second;
  refused.pixel(1, 1)[0] = -1.0f;
  for (std::size_t k = 3; k < refused.rgba.size(); k += 4) refused.rgba[k] = 0.9f;
  refused.depth.assign(static_cast<std::size_t>(refused.width_px) * refused.height_px, 7.0f);
  EXPECT_THROW(convolution.set_scene(refused), std::invalid_argument);
  EXPECT_THROW(convolution.set_scene(hdr_frame(32)), std::invalid_argument);
  ImageRGBA again;
  convolution.convolve(psf, again);
  EXPECT_EQ(again.rgba, out_second.rgba);
  EXPECT_EQ(again.depth, out_second.depth);
  // A scene with depth gives it to the result, and one without takes it away.
  second.depth.assign(static_cast<std::size_t>(second.width_px) * second.height_px, 2.5f);
  convolution.set_scene(second);
  convolution.convolve(psf, again);
  EXPECT_EQ(again.depth, second.depth);
  convolution.set_scene(first);
  convolution.convolve(psf, again);
  EXPECT_TRUE(again.depth.empty());
}

// Three lit regions on black: two rooms of one size (a lamp in each) and a strip at the frame's
// right edge (its glare is clipped there).
ImageRGBA three_region_frame() {
  ImageRGBA frame(400, 200, 0.0f);
  for (const int left : {20, 150})
    for (int y = 30; y < 90; ++y)
      for (int x = left; x < left + 70; ++x) {
        const bool lamp = std::abs(x - left - 35) < 3 && std::abs(y - 50) < 3;
        float* p = frame.pixel(x, y);
        p[0] = lamp ? 900.0f : 0.4f + 0.001f * static_cast<float>(x);
        p[1] = lamp ? 1000.0f : 0.5f;
        p[2] = lamp ? 700.0f : 0.3f + 0.002f * static_cast<float>(y);
      }
  for (int y = 120; y < 190; ++y)
    for (int x = 385; x < 400; ++x) frame.pixel(x, y)[1] = 5.0f;
  for (std::size_t k = 3; k < frame.rgba.size(); k += 4) frame.rgba[k] = 0.75f;
  return frame;
}

TEST(GlareCpuFloat, RegionsConvolvedOnTheirOwnEqualTheWholeFrameInDouble) {
  CpuFloatGlareSettings settings;
  settings.grid_px = 64;
  settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(575.0, kWidthMm);
  CpuFloatGlare glare(settings);
  for (const int m : {17, 18}) {  // odd and even: the reach before and after the centre differ
    ImageRGBA frame = three_region_frame();
    const Psf psf = test::lopsided_psf(m);
    const std::vector<PixelRect> boxes = lit_regions(frame, m);
    ASSERT_EQ(boxes.size(), 3u);
    const ImageRGBA reference = convolve_image_cpu(frame, psf, ConvolutionOptions{});
    ImageRGBA out = frame;
    glare.convolve_regions(frame, boxes, psf, out);
    EXPECT_FALSE(glare.reused_scene());
    EXPECT_LT(relative_l2(rgb_of(out), rgb_of(reference)), 1e-6) << m;
    // Every pixel, also far from the lamps: the glare of the dim strip at the edge, and black
    // between the regions' reach.
    double worst = 0.0;
    for (std::size_t k = 0; k < out.rgba.size(); ++k)
      if (k % 4 != 3) worst = std::max(worst, std::abs(static_cast<double>(out.rgba[k]) - reference.rgba[k]));
    EXPECT_LT(worst, 1e-6 * 1000.0) << m;
    EXPECT_EQ(out.pixel(250, 10)[1], 0.0f) << "beyond every region's reach";
    EXPECT_GT(out.pixel(380, 150)[1], 0.0f) << "the strip's glare";
    EXPECT_EQ(out.pixel(200, 100)[3], 0.75f);  // alpha untouched
    // The same frame again: the kept spectra serve, bit for bit the same result.
    ImageRGBA again = frame;
    glare.convolve_regions(frame, boxes, psf, again);
    EXPECT_TRUE(glare.reused_scene());
    EXPECT_EQ(again.rgba, out.rgba);
    // One room changes: its spectrum is made again, and the result is that frame's.
    for (int y = 30; y < 90; ++y) frame.pixel(180, y)[0] = 50.0f;
    const ImageRGBA changed_reference = convolve_image_cpu(frame, psf, ConvolutionOptions{});
    ImageRGBA changed = frame;
    glare.convolve_regions(frame, lit_regions(frame, m), psf, changed);
    EXPECT_FALSE(glare.reused_scene());
    EXPECT_LT(relative_l2(rgb_of(changed), rgb_of(changed_reference)), 1e-6) << m;
  }
}

// `same` output pads only by half the PSF (image + M/2, at least M): the folded-back end of the
// circular convolution lands in rows and columns that are not read. Checked against the float64
// convolution for odd and even PSFs, one wider than the image, and sizes at the bound.
TEST(GlareCpuFloat, SamePaddingIsHalfThePsfAndStillTheLinearConvolution) {
  struct Case {
    int width, height, m, rows, cols;
  };
  // rows = smallest 2,3,5-smooth >= max(height + m / 2, m), cols likewise from the width.
  for (const Case& c : {Case{64, 48, 8, 54, 72}, Case{60, 45, 15, 54, 72}, Case{40, 12, 31, 32, 60},
                        Case{25, 25, 25, 40, 40}, Case{97, 33, 2, 36, 100},
                        Case{50, 44, 8, 48, 54}}) {  // the last exactly at the bound both ways
    const ImageRGBA image = [&] {
      ImageRGBA frame(c.width, c.height, 0.0f);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
          for (int channel = 0; channel < 3; ++channel)
            frame.pixel(x, y)[channel] = 0.2f + 0.01f * static_cast<float>((x * 5 + y * 11 + channel * 3) % 13);
      // Lamps at the corners: their glare is what would fold back across the image.
      frame.pixel(0, 0)[0] = 800.0f;
      frame.pixel(c.width - 1, c.height - 1)[1] = 900.0f;
      frame.pixel(c.width - 1, 0)[2] = 700.0f;
      return frame;
    }();
    const Psf psf = test::lopsided_psf(c.m);
    CpuFloatConvolution convolution(c.width, c.height, c.m);
    EXPECT_EQ(convolution.fft_rows(), c.rows) << c.width << " x " << c.height << ", M " << c.m;
    EXPECT_EQ(convolution.fft_cols(), c.cols) << c.width << " x " << c.height << ", M " << c.m;
    convolution.set_scene(image);
    ImageRGBA out;
    convolution.convolve(psf, out);
    const ImageRGBA reference = convolve_image_cpu(image, psf, ConvolutionOptions{});
    EXPECT_LT(relative_l2(rgb_of(out), rgb_of(reference)), 1e-6) << c.width << " x " << c.height << ", M " << c.m;
  }
}

TEST(GlareCpuFloat, RegionConvolutionRefusesBadInputAndMisuse) {
  CpuFloatConvolution full(30, 20, 9, 2, ConvolutionOutput::full, 2);
  EXPECT_EQ(full.slots(), 2);
  EXPECT_EQ(full.fft_rows(), 30);  // 20 + 9 - 1 = 28 is 4 x 7: the next 2,3,5-smooth size
  EXPECT_EQ(full.fft_cols(), 40);  // 30 + 9 - 1 = 38 is 2 x 19: the next smooth size
  ImageRGBA frame(100, 50, 1.0f);
  ImageRGBA out = frame;
  EXPECT_THROW(full.write_full(0, out, 10, 10), std::logic_error);  // no scene, no kernel
  EXPECT_THROW(full.set_scene(frame, 80, 10, 0), std::invalid_argument);  // not inside the frame
  EXPECT_THROW(full.set_scene(frame, 10, 10, 2), std::invalid_argument);  // no such slot
  frame.pixel(15, 12)[1] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(full.set_scene(frame, 10, 10, 0), std::invalid_argument);
  ImageRGBA image(30, 20, 1.0f);
  EXPECT_THROW(full.convolve(test::lopsided_psf(9), image), std::logic_error);  // `same` only
  CpuFloatGlare glare([] {
    CpuFloatGlareSettings settings;
    settings.grid_px = 64;
    settings.display_degrees_per_pixel = 4.0 * psf_degrees_per_pixel(575.0, kWidthMm);
    return settings;
  }());
  ImageRGBA small(20, 20, 1.0f);
  EXPECT_THROW(glare.convolve_regions(frame, {PixelRect{90, 0, 20, 10}}, test::lopsided_psf(9), out), std::invalid_argument);
  EXPECT_THROW(glare.convolve_regions(frame, {PixelRect{0, 0, 10, 10}}, test::lopsided_psf(9), small), std::invalid_argument);
}

TEST(GlareCpuFloat, ClosedApertureAndDisplayTooFineAreRefused) {
  CpuFloatPsfSettings settings;
  settings.raster.grid_px = 32;
  CpuFloatPsf psf(settings);
  ApertureGeometry closed;
  closed.pupil_diameter_mm = 4.0;
  closed.discs.push_back({0.0, 0.0, 3.0, 0.0});
  psf.rasterise(closed);
  EXPECT_THROW(psf.transform(closed.pupil_diameter_mm, 0.0), ClosedApertureError);
  CpuFloatSpectralSettings spectral;
  spectral.grid_px = 32;
  spectral.psf_degrees_per_pixel = psf.degrees_per_pixel();
  spectral.display_degrees_per_pixel = 0.5 * psf.degrees_per_pixel();
  EXPECT_THROW(CpuFloatSpectralPsf{spectral}, PsfScaleError);
}

TEST(GlareCpuFloat, FftwFloorRunsItsTenTransforms) {
  FftwFloatFloor floor(32, 40, 48, 2);
  floor.run();
  floor.run();
  EXPECT_THROW(FftwFloatFloor(1, 40, 48), std::invalid_argument);
}

// The floor's measured plans leave no wisdom behind: an estimated plan of the floor's own N x N
// problem made after it is the one made before it, bit for bit (FFTW would otherwise reuse the
// measured plan, whose rounding differs).
TEST(GlareCpuFloat, EstimatedPlansAfterTheFloorAreThePlansBeforeIt) {
  const int n = 256;
  const auto transform = [&] {
    FftwFloatBuffer<std::complex<float>> in(static_cast<std::size_t>(n) * n), out(static_cast<std::size_t>(n) * n);
    const FftwFloatPlan plan = FftwFloatPlan::complex_forward(n, n, in.data(), out.data(), 2);
    for (std::size_t k = 0; k < in.size(); ++k)
      in[k] = {static_cast<float>(std::sin(0.37 * static_cast<double>(k))), static_cast<float>(std::cos(0.11 * static_cast<double>(k % 1000)))};
    plan.execute();
    return std::vector<std::complex<float>>(out.data(), out.data() + out.size());
  };
  const std::vector<std::complex<float>> before = transform();
  { FftwFloatFloor floor(n, 40, 48, 2); }
  const std::vector<std::complex<float>> after = transform();
  ASSERT_EQ(before.size(), after.size());
  EXPECT_EQ(0, std::memcmp(before.data(), after.data(), before.size() * sizeof(std::complex<float>)));
}

}  // namespace
}  // namespace glarelab
