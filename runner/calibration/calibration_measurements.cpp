#include "runner/calibration/calibration_measurements.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"

namespace glarelab {
namespace {

// The shortest text that reads back to the same double (std::to_chars without a format, C++17
// [charconv]): a reading typed as 0.35 is written 0.35, a computed one keeps all its digits.
std::string round_trip_text(double value) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  return std::string(buffer, end);
}

// Which reading of the file it is: the caller's ConfigError already gives its file:line:column, so
// the location is not repeated here. Typed readings (line 0) have neither.
std::string where(const std::vector<PatchReading>& readings, const PatchReading& reading) {
  if (reading.line == 0) return "";
  return " (reading " + std::to_string(&reading - readings.data() + 1) + " of " + std::to_string(readings.size()) + ")";
}

}  // namespace

std::vector<PatchReading> read_measurements_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError({path, 0, 0}, "measurements", "cannot read the measurements file");
  std::vector<PatchReading> readings;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::size_t position = 0;
    while (position < line.size()) {
      position = line.find_first_not_of(" \t,", position);
      if (position == std::string::npos) break;
      const std::size_t end = std::min(line.find_first_of(" \t,", position), line.size());
      const std::string field = line.substr(position, end - position);
      double value = 0.0;
      const auto [stop, error] = std::from_chars(field.data(), field.data() + field.size(), value);
      if (error != std::errc() || stop != field.data() + field.size() || !std::isfinite(value))
        throw ConfigError({path, line_number, static_cast<int>(position) + 1}, "measurements",
                          "expected a luminance in cd/m2, found '" + field + "'");
      readings.push_back({value, line_number, static_cast<int>(position) + 1});
      position = end;
    }
  }
  return readings;
}

std::optional<ReadingProblem> check_readings(const CalibrationPlan& plan, const std::vector<PatchReading>& readings,
                                             const std::string& /*file: named by the caller's ConfigError*/) {
  if (readings.size() != plan.patches.size())
    return ReadingProblem{0, "expected " + std::to_string(plan.patches.size()) + " luminances (" +
                                 std::to_string(plan.levels) +
                                 " levels x 4 patches: red, green, blue, white, in that order), found " +
                                 std::to_string(readings.size())};
  for (std::size_t i = 0; i < readings.size(); ++i) {
    if (readings[i].luminance_cd_m2 < 0.0)
      return ReadingProblem{i, plan.describe(plan.patches[i]) + where(readings, readings[i]) + ": negative luminance " +
                                   number_text(readings[i].luminance_cd_m2) + " cd/m2"};
  }
  for (PatchChannel channel : kPatchChannels) {
    const std::size_t first = static_cast<std::size_t>(static_cast<int>(channel) * plan.levels);
    for (int level = 1; level < plan.levels; ++level) {
      const PatchReading& before = readings[first + static_cast<std::size_t>(level) - 1];
      const PatchReading& now = readings[first + static_cast<std::size_t>(level)];
      // A luminance that falls as the drive rises cannot be inverted (docs/DISPLAY_CALIBRATION.md):
      // a reading taken before the display settled, or a photometer at its noise floor.
      if (now.luminance_cd_m2 < before.luminance_cd_m2)
        return ReadingProblem{first + static_cast<std::size_t>(level),
                              plan.describe(plan.patches[first + static_cast<std::size_t>(level)]) + where(readings, now) +
                                  ": " + number_text(now.luminance_cd_m2) + " cd/m2 is less than the " +
                                  number_text(before.luminance_cd_m2) +
                                  " cd/m2 of the level below: the luminance must not fall as the drive rises"};
    }
    const PatchReading& black = readings[first];
    const PatchReading& full = readings[first + static_cast<std::size_t>(plan.levels) - 1];
    if (!(full.luminance_cd_m2 > black.luminance_cd_m2))
      return ReadingProblem{first + static_cast<std::size_t>(plan.levels) - 1,
                            std::string(to_string(channel)) + where(readings, full) + ": full drive (" +
                                number_text(full.luminance_cd_m2) + " cd/m2) is not brighter than black (" +
                                number_text(black.luminance_cd_m2) + " cd/m2)"};
  }
  return std::nullopt;
}

std::string calibration_csv(const CalibrationPlan& plan, const std::vector<PatchReading>& readings,
                            const std::string& header_comment) {
  std::ostringstream csv;
  if (!header_comment.empty()) csv << "# " << header_comment << "\n";
  // White is not part of the per-channel table; kept here for the additivity check (step 5 of
  // "Measuring a display with a photometer").
  csv << "# white_cd_m2 at the same levels:";
  for (int level = 0; level < plan.levels; ++level)
    csv << (level == 0 ? " " : ", ")
        << round_trip_text(readings[static_cast<std::size_t>(3 * plan.levels + level)].luminance_cd_m2);
  csv << "\n";
  const bool codes = plan.full_code() > 0;
  csv << (codes ? "code" : "drive") << ",red_cd_m2,green_cd_m2,blue_cd_m2\n";
  for (int level = 0; level < plan.levels; ++level) {
    const CalibrationPatch& patch = plan.patch(PatchChannel::red, level);
    csv << (codes ? std::to_string(patch.code) : round_trip_text(patch.drive));
    for (int channel = 0; channel < 3; ++channel)
      csv << "," << round_trip_text(readings[static_cast<std::size_t>(channel * plan.levels + level)].luminance_cd_m2);
    csv << "\n";
  }
  return csv.str();
}

}  // namespace glarelab
