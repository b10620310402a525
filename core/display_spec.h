#pragma once
// The physical display a session shows its frames on: size, refresh rate, viewing geometry and
// photometry. Plain data, read from the experiment file by protocols/ and modelled by
// stimuli/display_model.h; it sits in the base layer because both need it and neither may include
// the other (docs/ARCHITECTURE.md).
#include "core/display_calibration.h"

namespace glarelab {

// How luminance becomes a drive value (docs/DISPLAY_CALIBRATION.md): relative to the peak through
// sRGB or a power law; absolute through SMPTE ST 2084 (PQ); or through a measured calibration table.
enum class DisplayEncoding { srgb, gamma, pq, table };
// The primaries the drive values address (with encoding pq): the stimulus is linear Rec.709 and
// is converted to BT.2020 primaries (ITU-R BT.2087 matrix) when the display takes BT.2020.
enum class DisplayPrimaries { rec709, bt2020 };
// Per-eye rendering ([display] stereo; stimuli/stereo_layout.h): one view for both eyes, or the
// left eye's view in the left half of the frame and the right eye's in the right half (HMD mirror
// windows, side-by-side stereo displays).
enum class StereoMode { none, side_by_side };

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
  DisplayPrimaries primaries = DisplayPrimaries::rec709;  // used when encoding == pq
  DisplayCalibration calibration;  // used when encoding == table; its peak is peak_luminance_cd_m2
  // Depth of the framebuffer the encoded frame is written to: 8 (RGBA8, ordered dithering), 10
  // (RGB10_A2), 16 (RGBA16F), or 0: the backend's own default framebuffer, unquantised offscreen.
  int bits_per_channel = 0;
  int monitor = 0;
  bool fullscreen = false;
  StereoMode stereo = StereoMode::none;
  // Background between side-by-side stimuli (stimuli/layout.h): the columns are this many degrees
  // apart, so two scenes never abut and read as one picture. 0: the columns tile the display.
  double stimulus_gap_deg = 0.0;
};

// Visual angle (degrees) of a span of `pixels` centred on the line of sight:
// 2 atan(pixels * pitch / 2d).
double centred_span_deg(const DisplaySpec& display, double pixels);
// The inverse: pixels of a span centred on the line of sight that subtends `degrees`,
// 2 d tan(degrees / 2) / pitch (not rounded).
double centred_span_px(const DisplaySpec& display, double degrees);
// stimulus_gap_deg in whole pixels: the centred span, rounded to the nearest pixel (the gap
// between two stimuli lies on the line of sight).
int stimulus_gap_px(const DisplaySpec& display);

}  // namespace glarelab
