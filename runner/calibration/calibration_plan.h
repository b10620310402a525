#pragma once
// The patches `glarelab calibrate` shows a photometer, in the order it shows them: each primary
// alone (red, green, blue) and then white, each at the same drive levels from 0 (black) to full
// drive (docs/DISPLAY_CALIBRATION.md, "Measuring a display with a photometer"). A level is sent as
// a whole code value of the framebuffer's depth (8 or 10 bits) or, for a half-float framebuffer,
// as the drive itself, so the table records what the display was actually sent.
#include <array>
#include <string>
#include <vector>

namespace glarelab {

enum class PatchChannel { red, green, blue, white };
inline constexpr std::array<PatchChannel, 4> kPatchChannels = {PatchChannel::red, PatchChannel::green,
                                                               PatchChannel::blue, PatchChannel::white};
const char* to_string(PatchChannel channel);

struct CalibrationPatch {
  PatchChannel channel = PatchChannel::red;
  int level = 0;       // 0 .. levels - 1 within the channel
  double drive = 0.0;  // what the framebuffer holds, in [0, 1]: code / full_code, or the half-float drive
  int code = -1;       // the whole code value sent (8 or 10 bits); -1 for a half-float framebuffer
  // The drive of each framebuffer channel: (drive, 0, 0) for red ... (drive, drive, drive) for white.
  std::array<double, 3> rgb_drive() const;
};

struct CalibrationPlan {
  int levels = 0;
  int bits_per_channel = 8;  // 8 or 10 (codes), 16 (half float: drives)
  std::vector<CalibrationPatch> patches;  // channel by channel, levels rising
  // The largest code (255, 1023); 0 for half float.
  int full_code() const;
  const CalibrationPatch& patch(PatchChannel channel, int level) const;
  // "red level 3 of 17 (code 48 of 255)" or "(drive 0.1875)".
  std::string describe(const CalibrationPatch& patch) const;
};

// Level i of n asks for drive i / (n - 1), sent as the nearest code (8 or 10 bits; codes must then
// rise strictly, so n is at most 2^bits) or as that drive rounded to half float (16). Throws
// std::invalid_argument naming the flag for fewer than 2 levels, too many for the depth, or a depth
// other than 8, 10 or 16.
CalibrationPlan make_calibration_plan(int levels, int bits_per_channel);

// The most levels a plan of that depth takes.
int max_calibration_levels(int bits_per_channel);

}  // namespace glarelab
