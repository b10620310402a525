#pragma once
// The luminances a photometer read off the calibration patches (cd/m2, one per patch in the plan's
// order), their checks, and the calibration CSV they become: the file `encoding = "table"` reads
// (core/display_calibration.h, docs/DISPLAY_CALIBRATION.md "Calibration CSV format").
#include <optional>
#include <string>
#include <vector>

#include "runner/calibration/calibration_plan.h"

namespace glarelab {

// One reading and where it came from (a file's line and column, or the patch it was typed for).
struct PatchReading {
  double luminance_cd_m2 = 0.0;
  int line = 0;    // in the measurements file; 0 when typed
  int column = 0;
};

// A measurements file: one luminance (cd/m2) per patch, in the order the patches are shown (red
// levels rising, then green, blue and white), one per line; blank lines and lines starting with '#'
// are skipped, and a line may hold several values separated by commas or blanks. Throws ConfigError
// "FILE:LINE:COLUMN: key 'measurements': ..." for an unreadable file or a value that is not a finite
// number; the count and the shape are checked by check_readings.
std::vector<PatchReading> read_measurements_file(const std::string& path);

// The first thing wrong with the readings for this plan, as a sentence naming the patch (and,
// read from a file, which reading of it: the caller's ConfigError gives the file:line:column), or nothing: a count other than one per patch, a negative
// value, a luminance that falls as the drive rises within a channel, or a channel whose full drive
// is not brighter than its black (the table could not be inverted). `file` is not repeated in the message.
struct ReadingProblem {
  std::size_t patch_index = 0;  // the patch to measure again (0 for a wrong count)
  std::string message;
};
std::optional<ReadingProblem> check_readings(const CalibrationPlan& plan, const std::vector<PatchReading>& readings,
                                             const std::string& file);

// The calibration CSV: a comment header (what made it, the white readings, which the table does not
// hold but the additivity check uses), then `code` (8 or 10 bits) or `drive` (half float) and the
// three primaries' luminances, one row per level. Values are written as the shortest text that
// reads back to the same double.
std::string calibration_csv(const CalibrationPlan& plan, const std::vector<PatchReading>& readings,
                            const std::string& header_comment);

}  // namespace glarelab
