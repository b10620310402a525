#pragma once
// Tidy (long-format) CSV export: one row per trial, per frame, per tracker sample, with units in
// the column names, RFC 4180 quoting, empty cells for NULL and numbers written with 17
// significant digits so that a reader gets the stored doubles back exactly.
#include <optional>
#include <string>
#include <vector>

#include "analysis/loaded_database.h"

namespace glarelab::analysis {

// RFC 4180 field: quoted (with doubled quotes) when it holds a comma, quote, CR or LF, or
// leading/trailing spaces. Text a spreadsheet would run as a formula (starting with = + - @, a tab
// or a carriage return, and not a number) gets a leading apostrophe, unless
// keep_formula_cells_raw(true) was called (analyze --raw-csv-cells).
std::string csv_field(const std::string& value);
void keep_formula_cells_raw(bool raw);
// Shortest round-trip text for a double (std::to_chars).
std::string csv_number(double value);

// Column name for a condition key: "condition_" + the key with every character other than
// [A-Za-z0-9_] replaced by '_'.
std::string condition_column(const std::string& key);

// Writes trials.csv, frames.csv and tracker_samples.csv (and adjustments.csv when any trial
// has adjustment rows) into `directory`, each written beside its name and renamed into place, with
// the permission bits `mode` when given (the database's: an export holds the same data); returns
// the files written.
std::vector<std::string> write_tidy_csv(const LoadedData& data, const std::string& directory,
                                        std::optional<unsigned> mode = std::nullopt);

}  // namespace glarelab::analysis
