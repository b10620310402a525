#pragma once
// The screen shown while the response device is unplugged: the message of
// runner/session/response_device_input.h as text (stimuli/text_image.h), centred on the display's
// background.
#include "protocols/experiment.h"
#include "stimuli/frame_renderer.h"
#include "core/image.h"

namespace glarelab {

// Luminance of the message's text: 40 % of the display's peak (100 cd/m2 on a 250 cd/m2 display),
// readable without dazzling an observer adapted to a dim stimulus.
double device_pause_text_cd_m2(const DisplaySpec& display);
// The message in cd/m2, wrapped to 90 % of the screen width.
ImageRGBA device_pause_message_image(const DisplaySpec& display, int screen_width_px);
// An image centred on the screen (cropped by the screen when larger).
Placement centred_placement(const SceneTexture& image, int screen_width_px, int screen_height_px);
// Pixels whose luminance (Rec.709 Y) is at least `threshold_cd_m2`.
long lit_pixels(const ImageRGBA& image, double threshold_cd_m2);

}  // namespace glarelab
