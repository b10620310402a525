#pragma once
// CSV condition tables (RFC 4180: quoted fields, doubled quotes, CRLF or LF). The first row names
// the columns. Every cell remembers its line and column for error messages.
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

// Throws ConfigError for a missing file (location = referencing site passed as `referenced_from`),
// unterminated quotes, ragged rows, empty or duplicate column names.
CsvTable read_csv_file(const std::string& path, const SourceLocation& referenced_from);
CsvTable parse_csv_text(const std::string& text, const std::string& file_name);

}  // namespace glarelab
