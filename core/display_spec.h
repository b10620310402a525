#pragma once
// The physical display a session shows its frames on: size, refresh rate, viewing geometry and
// photometry. Plain data, read from the experiment file by protocols/ and modelled by
// stimuli/display_model.h; it sits in the base layer because both need it and neither may include
// the other (docs/ARCHITECTURE.md).

namespace glarelab {

enum class DisplayEncoding { srgb, gamma };

struct DisplaySpec {
  int width_px = 1280;
  int height_px = 720;
  double refresh_hz = 60.0;
  double viewing_distance_mm = 600.0;
  double pixel_pitch_mm = 0.25;
  double peak_luminance_cd_m2 = 250.0;  // white of the display; brighter stimulus values clip
  double background_cd_m2 = 0.0;        // luminance around and between stimuli
  DisplayEncoding encoding = DisplayEncoding::srgb;
  double gamma = 2.2;  // used when encoding == gamma
  int monitor = 0;
  bool fullscreen = false;
};

// Visual angle (degrees) of a span of `pixels` centred on the line of sight:
// 2 atan(pixels * pitch / 2d).
double centred_span_deg(const DisplaySpec& display, double pixels);
// The inverse: pixels of a span centred on the line of sight that subtends `degrees`,
// 2 d tan(degrees / 2) / pitch (not rounded).
double centred_span_px(const DisplaySpec& display, double degrees);

}  // namespace glarelab
