#pragma once
// A display's measured photometric response (docs/DISPLAY_CALIBRATION.md): the luminance of each
// primary alone (red, green, blue; the other two at drive 0) at a series of drive levels, read
// with a photometer. Used by `encoding = "table"` to turn a wanted luminance into a drive value
// by inverting the measured curve (piecewise linear in luminance between measured points).
//
// Model (the additivity assumed by every per-channel calibration, Brainard 1989 "Calibration of a
// computer controlled color monitor"): the screen shows black_cd_m2 at drive (0, 0, 0), and each
// primary adds L_c(d) - L_c(0) on top, so white (1, 1, 1) is
// black_cd_m2 + sum_c (L_c(1) - L_c(0)) = peak_cd_m2().
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace glarelab {

struct DisplayCalibration {
  std::string file;  // where the table was read from (absolute when read through an experiment file)
  // Drive levels normalised to [0, 1]: strictly increasing, first 0 (black), last 1 (full drive).
  std::vector<double> drive;
  // Measured luminance (cd/m2) of red, green and blue alone at each drive level: non-decreasing.
  std::array<std::vector<double>, 3> luminance_cd_m2;

  bool empty() const { return drive.empty(); }
  std::size_t rows() const { return drive.size(); }
  // Luminance of the screen at drive (0, 0, 0): the mean of the three channels' drive-0 readings
  // (each is a reading of the same black screen).
  double black_cd_m2() const;
  // Luminance of white (1, 1, 1) under additivity: black + the three channels' full-drive gains.
  double peak_cd_m2() const;
  // What channel c adds above its drive-0 reading at drive `drive01` (piecewise linear between
  // the measured points; drive clipped to [0, 1]), cd/m2.
  double channel_gain_cd_m2(int channel, double drive01) const;
  // The inverse: the drive in [0, 1] at which channel c adds `gain_cd_m2` (clipped to what the
  // channel can add), interpolating linearly in luminance between the two measured points around
  // it. Where the measured curve is flat the lowest drive reaching the gain is returned.
  double drive_for_gain(int channel, double gain_cd_m2) const;
  // Drive values of the three channels that show a linear Rec.709 stimulus (cd/m2 per channel,
  // white = equal channels): each channel carries the fraction (s_c - black) / (peak - black) of
  // its full gain, so an achromatic stimulus of Y cd/m2 shows Y (clipped to [black, peak]).
  std::array<double, 3> drive_for_stimulus(const std::array<double, 3>& stimulus_cd_m2) const;
};

// Reads a calibration CSV (format in docs/DISPLAY_CALIBRATION.md). Throws ConfigError
// "FILE:LINE:COLUMN: display calibration: ..." for a missing or unreadable file, missing or
// unknown columns, a non-number, a negative value, drive levels that do not rise from 0 to full
// drive, a luminance that falls as drive rises, fewer than 2 rows, or a channel that never rises.
DisplayCalibration read_display_calibration(const std::string& path);
// The same from text; `file_name` is used in messages.
DisplayCalibration parse_display_calibration(std::string_view text, const std::string& file_name);

}  // namespace glarelab
