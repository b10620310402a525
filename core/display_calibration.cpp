#include "core/display_calibration.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/number_text.h"

namespace glarelab {
namespace {

constexpr const char* kSubsystem = "display calibration: ";
constexpr std::array<const char*, 3> kChannelColumns = {"red_cd_m2", "green_cd_m2", "blue_cd_m2"};

struct Field {
  std::string text;
  int column = 0;  // 1-based character column of the field's first character after leading blanks
};

[[noreturn]] void fail(const std::string& file, int line, int column, const std::string& message) {
  throw ConfigError(SourceLocation{file, line, column}, "", kSubsystem + message);
}

std::vector<Field> split_fields(std::string_view line) {
  std::vector<Field> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    std::size_t first = start;
    while (first < end && (line[first] == ' ' || line[first] == '\t')) ++first;
    std::size_t last = end;
    while (last > first && (line[last - 1] == ' ' || line[last - 1] == '\t')) --last;
    fields.push_back({std::string(line.substr(first, last - first)), static_cast<int>(first) + 1});
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

double parse_number(const std::string& file, int line, const Field& field, const std::string& column_name) {
  double value = 0.0;
  const char* begin = field.text.data();
  const char* end = begin + field.text.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  if (field.text.empty() || error != std::errc() || stop != end || !std::isfinite(value))
    fail(file, line, field.column, "column '" + column_name + "': expected a number, found '" + field.text + "'");
  if (value < 0.0)
    fail(file, line, field.column, "column '" + column_name + "': negative value " + field.text);
  return value;
}

// The segment [i, i + 1] of `values` (sorted, non-decreasing) that holds `value`, for
// interpolation: the first i + 1 with values[i + 1] >= value, so a flat run is never a divisor.
std::size_t segment_of(const std::vector<double>& values, double value) {
  const auto upper = std::lower_bound(values.begin() + 1, values.end() - 1, value);
  return static_cast<std::size_t>(upper - values.begin()) - 1;
}

}  // namespace

double DisplayCalibration::black_cd_m2() const {
  return (luminance_cd_m2[0].front() + luminance_cd_m2[1].front() + luminance_cd_m2[2].front()) / 3.0;
}

double DisplayCalibration::peak_cd_m2() const {
  double peak = black_cd_m2();
  for (const std::vector<double>& channel : luminance_cd_m2) peak += channel.back() - channel.front();
  return peak;
}

double DisplayCalibration::channel_gain_cd_m2(int channel, double drive01) const {
  const std::vector<double>& luminance = luminance_cd_m2[static_cast<std::size_t>(channel)];
  const double d = std::clamp(drive01, 0.0, 1.0);
  const std::size_t i = segment_of(drive, d);
  const double t = (d - drive[i]) / (drive[i + 1] - drive[i]);  // drive is strictly increasing
  return luminance[i] + t * (luminance[i + 1] - luminance[i]) - luminance.front();
}

double DisplayCalibration::drive_for_gain(int channel, double gain_cd_m2) const {
  const std::vector<double>& luminance = luminance_cd_m2[static_cast<std::size_t>(channel)];
  const double wanted = std::clamp(luminance.front() + gain_cd_m2, luminance.front(), luminance.back());
  if (wanted <= luminance.front()) return 0.0;
  const std::size_t i = segment_of(luminance, wanted);  // luminance[i] < wanted <= luminance[i + 1]
  const double t = (wanted - luminance[i]) / (luminance[i + 1] - luminance[i]);
  return drive[i] + t * (drive[i + 1] - drive[i]);
}

std::array<double, 3> DisplayCalibration::drive_for_stimulus(const std::array<double, 3>& stimulus_cd_m2) const {
  const double black = black_cd_m2();
  const double span = peak_cd_m2() - black;
  std::array<double, 3> drives{};
  for (int c = 0; c < 3; ++c) {
    const std::vector<double>& luminance = luminance_cd_m2[static_cast<std::size_t>(c)];
    const double fraction = std::clamp((stimulus_cd_m2[static_cast<std::size_t>(c)] - black) / span, 0.0, 1.0);
    drives[static_cast<std::size_t>(c)] = drive_for_gain(c, fraction * (luminance.back() - luminance.front()));
  }
  return drives;
}

DisplayCalibration parse_display_calibration(std::string_view text, const std::string& file_name) {
  DisplayCalibration table;
  table.file = file_name;
  std::vector<Field> header;
  std::array<int, 4> column_of{-1, -1, -1, -1};  // field index of drive, red, green, blue
  bool codes = false;
  int line_number = 0;
  int last_line = 0;
  std::vector<int> drive_lines;
  std::vector<std::array<int, 4>> cell_columns;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t newline = text.find('\n', start);
    std::string_view line = text.substr(start, newline == std::string_view::npos ? std::string_view::npos : newline - start);
    start = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;  // blank line or comment
    last_line = line_number;
    const std::vector<Field> fields = split_fields(line);
    if (header.empty()) {
      header = fields;
      for (std::size_t i = 0; i < fields.size(); ++i) {
        const std::string& name = fields[i].text;
        int slot = -1;
        if (name == "drive" || name == "code") {
          slot = 0;
          codes = name == "code";
        }
        for (int c = 0; c < 3; ++c)
          if (name == kChannelColumns[static_cast<std::size_t>(c)]) slot = c + 1;
        if (slot < 0)
          fail(file_name, line_number, fields[i].column,
               "unknown column '" + name + "' (the columns are 'drive' or 'code', then 'red_cd_m2', 'green_cd_m2', 'blue_cd_m2')");
        if (column_of[static_cast<std::size_t>(slot)] >= 0)
          fail(file_name, line_number, fields[i].column, "column '" + name + "' given twice");
        column_of[static_cast<std::size_t>(slot)] = static_cast<int>(i);
      }
      const int end_column = static_cast<int>(line.size()) + 1;
      if (column_of[0] < 0) fail(file_name, line_number, end_column, "missing column 'drive' (0..1) or 'code' (0..full code)");
      for (int c = 0; c < 3; ++c)
        if (column_of[static_cast<std::size_t>(c) + 1] < 0)
          fail(file_name, line_number, end_column,
               std::string("missing column '") + kChannelColumns[static_cast<std::size_t>(c)] + "'");
      continue;
    }
    if (fields.size() < header.size())
      fail(file_name, line_number, static_cast<int>(line.size()) + 1,
           "missing column '" + header[fields.size()].text + "' (" + std::to_string(fields.size()) + " of " +
               std::to_string(header.size()) + " values)");
    if (fields.size() > header.size())
      fail(file_name, line_number, fields[header.size()].column,
           "more values than the " + std::to_string(header.size()) + " columns of the header");
    std::array<int, 4> columns{};
    for (std::size_t slot = 0; slot < 4; ++slot) {
      const Field& field = fields[static_cast<std::size_t>(column_of[slot])];
      const std::string& name = header[static_cast<std::size_t>(column_of[slot])].text;
      const double value = parse_number(file_name, line_number, field, name);
      columns[slot] = field.column;
      if (slot == 0) {
        if (codes && value != std::floor(value))
          fail(file_name, line_number, field.column, "column 'code': expected a whole code value, found " + field.text);
        if (!codes && value > 1.0)
          fail(file_name, line_number, field.column,
               "column 'drive': " + field.text + " above full drive 1 (use a 'code' column for code values)");
        if (!table.drive.empty() && value <= table.drive.back())
          fail(file_name, line_number, field.column,
               "drive levels must rise row by row: " + field.text + " after " + number_text(table.drive.back()));
        if (table.drive.empty() && value != 0.0)
          fail(file_name, line_number, field.column, "the first row must be drive 0 (black), found " + field.text);
        table.drive.push_back(value);
      } else {
        std::vector<double>& luminance = table.luminance_cd_m2[slot - 1];
        if (!luminance.empty() && value < luminance.back())
          fail(file_name, line_number, field.column,
               "non-monotonic luminance: '" + name + "' falls from " + number_text(luminance.back()) + " to " +
                   field.text + " cd/m2 as drive rises");
        luminance.push_back(value);
      }
    }
    drive_lines.push_back(line_number);
    cell_columns.push_back(columns);
  }
  if (header.empty()) fail(file_name, 0, 0, "empty file (expected a header 'drive,red_cd_m2,green_cd_m2,blue_cd_m2')");
  if (table.drive.size() < 2)
    fail(file_name, last_line, 0,
         "at least 2 rows are needed (black and full drive), found " + std::to_string(table.drive.size()));
  const double full = table.drive.back();
  if (!codes && full != 1.0)
    fail(file_name, drive_lines.back(), cell_columns.back()[0],
         "the last row must be full drive 1, found " + number_text(full));
  for (double& d : table.drive) d /= full;  // codes 0..N become 0..1; the last row is full drive
  for (int c = 0; c < 3; ++c) {
    const std::vector<double>& luminance = table.luminance_cd_m2[static_cast<std::size_t>(c)];
    if (luminance.back() <= luminance.front())
      fail(file_name, drive_lines.back(), cell_columns.back()[static_cast<std::size_t>(c) + 1],
           std::string("'") + kChannelColumns[static_cast<std::size_t>(c)] +
               "' does not rise from black to full drive: the display would show nothing of this channel");
  }
  return table;
}

DisplayCalibration read_display_calibration(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(SourceLocation{path, 0, 0}, "", std::string(kSubsystem) + "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_display_calibration(text.str(), path);
}

}  // namespace glarelab
