#pragma once
// CSV condition tables (RFC 4180: quoted fields, doubled quotes, CRLF or LF). The first row names
// the columns. Every cell remembers its line and column for error messages.
#include <functional>
#include <string>
#include <vector>

#include "core/errors.h"

namespace glarelab {

struct CsvCell {
  std::string text;
  SourceLocation where;
};

struct CsvTable {
  std::string file;
  std::vector<CsvCell> header;
  std::vector<std::vector<CsvCell>> rows;  // each row has header.size() cells (checked)

  // Column index by name, or -1.
  int column(const std::string& name) const;
  // Throws ConfigError at the header naming the missing column and the columns present.
  int require_column(const std::string& name) const;
};

// A cell as the row-by-row reader hands it: its text and where it starts (the file is the table's).
struct CsvField {
  std::string text;
  int line = 0;
  int column = 0;
};

// Throws ConfigError for a missing file (location = referencing site passed as `referenced_from`),
// unterminated quotes, ragged rows, empty or duplicate column names.
CsvTable read_csv_file(const std::string& path, const SourceLocation& referenced_from);
CsvTable parse_csv_text(const std::string& text, const std::string& file_name);

// The same reading and checks, row by row: each row's cells go to `row` as they are read, with the
// table so far (its header; the function may keep the cells by moving them), and the table
// returned holds the header alone. A table of a
// million rows is then held once, in whatever `row` makes of it, not also as a million vectors of
// cells that each name their file.
CsvTable read_csv_file_rows(const std::string& path, const SourceLocation& referenced_from,
                            const std::function<void(const CsvTable& header, std::vector<CsvField>& cells)>& row);

}  // namespace glarelab
