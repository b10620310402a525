#include "runner/calibration/calibration_plan.h"

#include <cmath>
#include <stdexcept>

#include "core/number_text.h"

namespace glarelab {
namespace {

// The nearest half-float value (IEEE 754 binary16: 11 significant bits, subnormals below 2^-14) of
// a drive in [0, 1]: what an RGBA16F framebuffer stores when it is cleared to that drive.
double round_to_half_float(double value) {
  if (value <= 0.0) return 0.0;
  const int exponent = std::max(static_cast<int>(std::floor(std::log2(value))), -14);
  const double quantum = std::ldexp(1.0, exponent - 10);
  return std::nearbyint(value / quantum) * quantum;
}

}  // namespace

const char* to_string(PatchChannel channel) {
  switch (channel) {
    case PatchChannel::red: return "red";
    case PatchChannel::green: return "green";
    case PatchChannel::blue: return "blue";
    case PatchChannel::white: return "white";
  }
  return "?";
}

std::array<double, 3> CalibrationPatch::rgb_drive() const {
  switch (channel) {
    case PatchChannel::red: return {drive, 0.0, 0.0};
    case PatchChannel::green: return {0.0, drive, 0.0};
    case PatchChannel::blue: return {0.0, 0.0, drive};
    case PatchChannel::white: return {drive, drive, drive};
  }
  return {0.0, 0.0, 0.0};
}

int CalibrationPlan::full_code() const { return bits_per_channel == 16 ? 0 : (1 << bits_per_channel) - 1; }

const CalibrationPatch& CalibrationPlan::patch(PatchChannel channel, int level) const {
  return patches.at(static_cast<std::size_t>(static_cast<int>(channel) * levels + level));
}

std::string CalibrationPlan::describe(const CalibrationPatch& patch) const {
  std::string text = std::string(to_string(patch.channel)) + " level " + std::to_string(patch.level + 1) + " of " +
                     std::to_string(levels);
  if (patch.code >= 0) return text + " (code " + std::to_string(patch.code) + " of " + std::to_string(full_code()) + ")";
  return text + " (drive " + number_text(patch.drive) + ")";
}

int max_calibration_levels(int bits_per_channel) { return bits_per_channel == 8 ? 256 : 1024; }

CalibrationPlan make_calibration_plan(int levels, int bits_per_channel) {
  if (bits_per_channel != 8 && bits_per_channel != 10 && bits_per_channel != 16)
    throw std::invalid_argument("calibrate: --bits-per-channel must be 8, 10 or 16, not " +
                                std::to_string(bits_per_channel));
  if (levels < 2 || levels > max_calibration_levels(bits_per_channel))
    throw std::invalid_argument("calibrate: --levels must be from 2 (black and full drive) to " +
                                std::to_string(max_calibration_levels(bits_per_channel)) + " at " +
                                std::to_string(bits_per_channel) + " bits per channel, not " + std::to_string(levels));
  CalibrationPlan plan;
  plan.levels = levels;
  plan.bits_per_channel = bits_per_channel;
  const int full = plan.full_code();
  for (PatchChannel channel : kPatchChannels) {
    for (int level = 0; level < levels; ++level) {
      const double wanted = static_cast<double>(level) / static_cast<double>(levels - 1);
      CalibrationPatch patch;
      patch.channel = channel;
      patch.level = level;
      if (full > 0) {
        // Rounding i * full / (n - 1) with n - 1 <= full keeps the codes strictly rising.
        patch.code = static_cast<int>(std::lround(wanted * full));
        patch.drive = static_cast<double>(patch.code) / full;
      } else {
        patch.drive = round_to_half_float(wanted);
      }
      plan.patches.push_back(patch);
    }
  }
  return plan;
}

}  // namespace glarelab
