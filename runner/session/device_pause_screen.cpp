#include "runner/session/device_pause_screen.h"

#include "runner/session/response_device_input.h"
#include "stimuli/text_image.h"

namespace glarelab {

double device_pause_text_cd_m2(const DisplaySpec& display) { return 0.4 * display.peak_luminance_cd_m2; }

ImageRGBA device_pause_message_image(const DisplaySpec& display, int screen_width_px) {
  TextImageStyle style;
  style.line_height_px = 32;
  style.max_width_px = 0.9 * screen_width_px;
  style.text_cd_m2 = device_pause_text_cd_m2(display);
  style.background_cd_m2 = display.background_cd_m2;
  return render_text_image(kDeviceUnpluggedMessage, style);
}

Placement centred_placement(const SceneTexture& image, int screen_width_px, int screen_height_px) {
  Placement placement;
  placement.scene = &image;
  placement.scale_cd_m2 = 1.0;  // the image is in cd/m2 already
  placement.rect = {(screen_width_px - image.width_px) / 2, (screen_height_px - image.height_px) / 2, image.width_px,
                    image.height_px};
  placement.clip = {0, 0, screen_width_px, screen_height_px};
  return placement;
}

long lit_pixels(const ImageRGBA& image, double threshold_cd_m2) {
  long count = 0;
  for (int y = 0; y < image.height_px; ++y)
    for (int x = 0; x < image.width_px; ++x) {
      const float* p = image.pixel(x, y);
      if (luminance_rec709(p[0], p[1], p[2]) >= threshold_cd_m2) ++count;
    }
  return count;
}

}  // namespace glarelab
