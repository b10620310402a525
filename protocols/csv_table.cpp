#include "protocols/csv_table.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace glarelab {

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i].text == name) return static_cast<int>(i);
  }
  return -1;
}

int CsvTable::require_column(const std::string& name) const {
  const int index = column(name);
  if (index >= 0) return index;
  std::string present;
  for (const CsvCell& cell : header) present += (present.empty() ? "'" : ", '") + cell.text + "'";
  SourceLocation where = header.empty() ? SourceLocation{file, 1, 1} : header.front().where;
  throw ConfigError(where, name,
                    "missing column '" + name + "' in " + file + " (columns: " + present + ")");
}

namespace {

// A single pass over the text, RFC 4180 with two relaxations that matter for hand-edited tables:
// LF alone ends a record as well as CRLF, and spaces/tabs around unquoted fields are dropped
// (inside quotes every character is kept). Columns count characters (UTF-8 code points), not
// bytes, so they match what an editor shows.
class CsvParser {
 public:
  CsvParser(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {
    // Spreadsheet programs often prefix a UTF-8 byte order mark; it is not part of the first name.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
  }

  // The next record's cells into `cells` (blank lines skipped); false at the end of the text.
  bool next_record(std::vector<CsvField>& cells) {
    while (pos_ < text_.size() && line_is_blank()) skip_line();
    if (pos_ >= text_.size()) return false;
    record(cells);
    return true;
  }

 private:
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }

  void advance() {
    const char c = text_[pos_++];
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if (c == '\r') {
      // CR LF counts once (at the LF); a lone CR ends a line by itself.
      if (at_end() || peek() != '\n') {
        ++line_;
        column_ = 1;
      }
    } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
      ++column_;  // continuation bytes of a UTF-8 sequence do not start a new character
    }
  }

  bool at_line_end() const { return at_end() || peek() == '\n' || peek() == '\r'; }

  void skip_line_end() {
    if (at_end()) return;
    if (peek() == '\r') {
      advance();
      if (!at_end() && peek() == '\n') advance();
    } else if (peek() == '\n') {
      advance();
    }
  }

  bool line_is_blank() const {
    for (std::size_t i = pos_; i < text_.size(); ++i) {
      const char c = text_[i];
      if (c == '\n' || c == '\r') return true;
      if (c != ' ' && c != '\t') return false;
    }
    return true;
  }

  void skip_line() {
    while (!at_line_end()) advance();
    skip_line_end();
  }

  void skip_blanks() {
    while (!at_end() && (peek() == ' ' || peek() == '\t')) advance();
  }

  SourceLocation here() const { return SourceLocation{file_, line_, column_}; }

  void record(std::vector<CsvField>& cells) {
    cells.clear();
    for (;;) {
      cells.push_back(field());
      if (at_end()) break;
      if (peek() == ',') {
        advance();
        continue;
      }
      skip_line_end();
      break;
    }
  }

  CsvField field() {
    skip_blanks();
    CsvField cell{std::string(), line_, column_};
    if (!at_end() && peek() == '"') {
      advance();
      for (;;) {
        if (at_end()) {
          throw ConfigError(SourceLocation{file_, cell.line, cell.column}, "",
                            "unterminated quoted field: the quote opened here is never closed");
        }
        const char c = peek();
        if (c == '"') {
          advance();
          if (!at_end() && peek() == '"') {  // "" inside quotes is one literal quote
            cell.text += '"';
            advance();
            continue;
          }
          break;
        }
        cell.text += c;
        advance();
      }
      skip_blanks();
      if (!at_end() && peek() != ',' && !at_line_end()) {
        throw ConfigError(here(), "",
                          "unexpected character after a closing quote (expected ',' or the end of the line)");
      }
      return cell;
    }
    std::size_t kept = 0;  // length without trailing blanks
    while (!at_end() && peek() != ',' && !at_line_end()) {
      const char c = peek();
      if (c == '"') {
        throw ConfigError(here(), "",
                          "quote inside an unquoted field (quote the whole field and double the quote)");
      }
      cell.text += c;
      if (c != ' ' && c != '\t') kept = cell.text.size();
      advance();
    }
    cell.text.resize(kept);
    return cell;
  }

  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
};

}  // namespace

// The byte offset of the first byte that does not belong to well-formed UTF-8 (RFC 3629: no
// overlong forms, no surrogates, at most U+10FFFF), or npos. Condition values and column names are
// written into the stored TOML configuration, which must be UTF-8 (the experiment_file fuzz target
// found a column name with a stray byte that the stored configuration could not read back).
static std::size_t first_invalid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x80) {
      ++i;
      continue;
    }
    int length = 0;
    std::uint32_t code = 0, minimum = 0;
    if ((byte & 0xE0) == 0xC0) length = 2, code = byte & 0x1F, minimum = 0x80;
    else if ((byte & 0xF0) == 0xE0) length = 3, code = byte & 0x0F, minimum = 0x800;
    else if ((byte & 0xF8) == 0xF0) length = 4, code = byte & 0x07, minimum = 0x10000;
    else return i;
    if (i + static_cast<std::size_t>(length) > text.size()) return i;
    for (int k = 1; k < length; ++k) {
      const auto next = static_cast<unsigned char>(text[i + static_cast<std::size_t>(k)]);
      if ((next & 0xC0) != 0x80) return i;
      code = (code << 6) | (next & 0x3F);
    }
    if (code < minimum || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return i;
    i += static_cast<std::size_t>(length);
  }
  return std::string::npos;
}

namespace {

// The header, checked (no empty or duplicate names), and every further record handed to `row`
// once its cell count is checked against the header's.
CsvTable parse_rows(std::string_view text, const std::string& file_name,
                    const std::function<void(const CsvTable& header, std::vector<CsvField>& cells)>& row) {
  if (const std::size_t bad = first_invalid_utf8(text); bad != std::string::npos) {
    int line = 1, column = 1;
    for (std::size_t i = 0; i < bad; ++i) {
      if (text[i] == '\n') ++line, column = 1;
      else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) ++column;
    }
    char byte_text[8];
    std::snprintf(byte_text, sizeof byte_text, "0x%02X", static_cast<unsigned char>(text[bad]));
    throw ConfigError(SourceLocation{file_name, line, column}, "",
                      std::string("not UTF-8: byte ") + byte_text + " (save the table as UTF-8)");
  }
  CsvTable table;
  table.file = file_name;
  CsvParser parser(text, file_name);
  std::vector<CsvField> cells;
  if (!parser.next_record(cells)) {
    throw ConfigError(SourceLocation{file_name, 1, 1}, "", "empty table: the first row must name the columns");
  }
  for (CsvField& field : cells)
    table.header.push_back(CsvCell{std::move(field.text), SourceLocation{file_name, field.line, field.column}});
  for (std::size_t i = 0; i < table.header.size(); ++i) {
    const CsvCell& cell = table.header[i];
    if (cell.text.empty()) {
      throw ConfigError(cell.where, "", "empty column name (column " + std::to_string(i + 1) + ")");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (table.header[j].text == cell.text) {
        throw ConfigError(cell.where, cell.text,
                          "duplicate column name '" + cell.text + "' (also column " + std::to_string(j + 1) + ")");
      }
    }
  }
  while (parser.next_record(cells)) {
    if (cells.size() != table.header.size()) {
      throw ConfigError(SourceLocation{file_name, cells.front().line, 1}, "",
                        "ragged row: expected " + std::to_string(table.header.size()) +
                            " fields (as in the header), found " + std::to_string(cells.size()));
    }
    row(table, cells);
  }
  return table;
}

// The whole file as text, read straight into one string of its size.
std::string read_table_text(const std::string& path, const SourceLocation& referenced_from) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw ConfigError(referenced_from, "", "condition table '" + path + "': file not found");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) {
    throw ConfigError(referenced_from, "", "condition table '" + path + "': cannot be opened");
  }
  std::string text;
  std::array<char, 1 << 16> buffer;
  while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
  return text;
}

}  // namespace

CsvTable parse_csv_text(const std::string& text, const std::string& file_name) {
  std::vector<std::vector<CsvCell>> rows;
  CsvTable table = parse_rows(text, file_name, [&](const CsvTable&, std::vector<CsvField>& cells) {
    std::vector<CsvCell>& record = rows.emplace_back();
    record.reserve(cells.size());
    for (CsvField& field : cells)
      record.push_back(CsvCell{std::move(field.text), SourceLocation{file_name, field.line, field.column}});
  });
  table.rows = std::move(rows);
  return table;
}

CsvTable read_csv_file(const std::string& path, const SourceLocation& referenced_from) {
  return parse_csv_text(read_table_text(path, referenced_from), path);
}

CsvTable read_csv_file_rows(const std::string& path, const SourceLocation& referenced_from,
                            const std::function<void(const CsvTable& header, std::vector<CsvField>& cells)>& row) {
  return parse_rows(read_table_text(path, referenced_from), path, row);
}

}  // namespace glarelab
