#include "stimuli/spencer_scenes.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "stimuli/disc_coverage.h"

namespace glarelab {
namespace {

void set_grey(ImageRGBA& image, int x, int y, double luminance_cd_m2) {
  float* p = image.pixel(x, y);
  p[0] = p[1] = p[2] = static_cast<float>(luminance_cd_m2);
  p[3] = 1.0f;
}

// Paints an axis-aligned rectangle (pixel units) over the image, each pixel blended by the part of
// its area the rectangle covers.
void paint_rectangle(ImageRGBA& image, double x0, double y0, double x1, double y1, double luminance_cd_m2) {
  for (int y = std::max(0, static_cast<int>(y0)); y < std::min(image.height_px, static_cast<int>(y1) + 1); ++y) {
    for (int x = std::max(0, static_cast<int>(x0)); x < std::min(image.width_px, static_cast<int>(x1) + 1); ++x) {
      const double c = std::max(0.0, std::min(x + 1.0, x1) - std::max(double(x), x0)) *
                       std::max(0.0, std::min(y + 1.0, y1) - std::max(double(y), y0));
      if (c <= 0.0) continue;
      const double under = image.pixel(x, y)[0];
      set_grey(image, x, y, under * (1.0 - c) + luminance_cd_m2 * c);
    }
  }
}

// Paints the source disc centred in the image over what is there, its coverage scaled so the most
// covered pixel is exactly `peak_cd_m2`: a source narrower than a pixel still peaks at that value.
void paint_source(ImageRGBA& image, double diameter_px, double peak_cd_m2) {
  const double c = 0.5 * image.width_px, r = 0.5 * diameter_px;
  double most = 0.0;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) most = std::max(most, disc_pixel_coverage(c, c, r, x, y));
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      const double cover = disc_pixel_coverage(c, c, r, x, y) / most;
      if (cover <= 0.0) continue;
      set_grey(image, x, y, image.pixel(x, y)[0] * (1.0 - cover) + peak_cd_m2 * cover);
    }
  }
}

}  // namespace

GeneratedScenePixels generated_scene_pixels(const GeneratedSceneSpec& spec, const DisplaySpec& display) {
  return {centred_span_px(display, spec.disc_diameter_deg), centred_span_px(display, spec.annulus_diameter_deg)};
}

ImageRGBA draw_generated_scene(const GeneratedSceneSpec& spec, const DisplaySpec& display) {
  const GeneratedScenePixels px = generated_scene_pixels(spec, display);
  const double size = spec.size_px;
  const std::string what = to_string(spec.generator) + ": ";
  if (spec.size_px < 1) throw std::invalid_argument(what + "size_px must be >= 1");
  if (!(px.disc_diameter_px > 0.0) || px.disc_diameter_px > size)
    throw std::invalid_argument(what + "the disc (" + std::to_string(px.disc_diameter_px) + " px) must fit the " +
                                std::to_string(spec.size_px) + " px image");
  if (!(spec.disc_fraction_of_peak > 0.0) || spec.disc_fraction_of_peak > 1.0)
    throw std::invalid_argument(what + "disc_fraction_of_peak must be in (0, 1]");
  const double peak_cd_m2 = display.peak_luminance_cd_m2;
  const double disc_cd_m2 = spec.disc_fraction_of_peak * peak_cd_m2;
  ImageRGBA image(spec.size_px, spec.size_px, 0.0f);
  for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 1.0f;
  const double c = 0.5 * size;

  switch (spec.generator) {
    case SceneGenerator::disc_annulus: {
      if (!(px.annulus_diameter_px > px.disc_diameter_px) || px.annulus_diameter_px > size)
        throw std::invalid_argument(what + "the annulus must be wider than the disc and fit the image");
      // Spencer 1995, section 4: the annulus has one third of the disc's intensity.
      const double annulus_cd_m2 = disc_cd_m2 / 3.0;
      const double r_disc = 0.5 * px.disc_diameter_px, r_annulus = 0.5 * px.annulus_diameter_px;
      for (int y = 0; y < spec.size_px; ++y) {
        for (int x = 0; x < spec.size_px; ++x) {
          const double inner = disc_pixel_coverage(c, c, r_disc, x, y);
          const double outer = disc_pixel_coverage(c, c, r_annulus, x, y);
          set_grey(image, x, y, disc_cd_m2 * inner + annulus_cd_m2 * (outer - inner));
        }
      }
      return image;
    }
    case SceneGenerator::light_source:
      paint_source(image, px.disc_diameter_px, disc_cd_m2);
      return image;
    case SceneGenerator::desk_lamp: {
      // The bulb hangs under the shade's opening at the image centre: the bulb must fit it.
      if (px.disc_diameter_px > 0.15 * size)
        throw std::invalid_argument(what + "the bulb (" + std::to_string(px.disc_diameter_px) +
                                    " px) must be at most 15 % of the image to fit under the lamp's shade");
      // Desk top (lower part), its front edge, the lamp's base, upright arm, reach and shade; the
      // bulb at the centre, below the shade.
      paint_rectangle(image, 0.0, 0.72 * size, size, size, kDeskTopFractionOfPeak * peak_cd_m2);
      paint_rectangle(image, 0.0, 0.72 * size, size, 0.745 * size, kDeskEdgeFractionOfPeak * peak_cd_m2);
      paint_rectangle(image, 0.14 * size, 0.67 * size, 0.34 * size, 0.72 * size, kLampBodyFractionOfPeak * peak_cd_m2);
      paint_rectangle(image, 0.23 * size, 0.30 * size, 0.25 * size, 0.67 * size, kLampBodyFractionOfPeak * peak_cd_m2);
      paint_rectangle(image, 0.23 * size, 0.30 * size, 0.50 * size, 0.32 * size, kLampBodyFractionOfPeak * peak_cd_m2);
      paint_rectangle(image, 0.40 * size, 0.32 * size, 0.60 * size, 0.43 * size, kLampShadeFractionOfPeak * peak_cd_m2);
      paint_source(image, px.disc_diameter_px, disc_cd_m2);
      return image;
    }
  }
  throw std::invalid_argument(what + "unknown generator");
}

}  // namespace glarelab
