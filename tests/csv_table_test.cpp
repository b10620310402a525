#include <gtest/gtest.h>

#include <string>

#include <vector>

#include <utility>

#include "protocols/csv_table.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_csv_text(text, "t.csv");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

// A table that is not UTF-8 is refused at the first bad byte (its values go into the stored TOML
// configuration, which must be UTF-8); well-formed multibyte text is kept as it is.
TEST(CsvTable, TextThatIsNotUtf8IsRefusedAtItsByteAndUtf8IsKept) {
  const CsvTable table = parse_csv_text("name,note\nr\xC3\xA9sum\xC3\xA9,\xE2\x82\xAC \xF0\x9F\x92\xA1\n", "t.csv");
  EXPECT_EQ(table.rows.at(0).at(0).text, "r\xC3\xA9sum\xC3\xA9");
  for (const auto& [text, where] : std::vector<std::pair<std::string, std::string>>{
           {"name,g\xFF\na,b\n", "t.csv:1:7"},          // a byte no UTF-8 sequence starts with
           {"name,x\nab,\xC3\n", "t.csv:2:4"},           // a sequence cut off
           {"name,x\nab,\xC0\xAF\n", "t.csv:2:4"},       // overlong '/'
           {"name,x\nab,\xED\xA0\x80\n", "t.csv:2:4"}}) {  // a UTF-16 surrogate
    try {
      parse_csv_text(text, "t.csv");
      FAIL() << "accepted " << where;
    } catch (const ConfigError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(where + ": ", 0), 0u) << error.what();
      EXPECT_NE(std::string(error.what()).find("not UTF-8: byte 0x"), std::string::npos) << error.what();
    }
  }
}

TEST(CsvTable, QuotesDoubledQuotesCommasAndNewlines) {
  const CsvTable table = parse_csv_text(
      "name,note\r\n"
      "\"a, b\",\"say \"\"hi\"\"\"\r\n"
      "c,\"two\nlines\"\r\n",
      "t.csv");
  ASSERT_EQ(table.header.size(), 2u);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[0][0].text, "a, b");
  EXPECT_EQ(table.rows[0][1].text, "say \"hi\"");
  EXPECT_EQ(table.rows[1][0].text, "c");
  EXPECT_EQ(table.rows[1][1].text, "two\nlines");
  EXPECT_EQ(table.rows[1][1].where.line, 3);
  EXPECT_EQ(table.rows[1][1].where.column, 3);
}

TEST(CsvTable, TrimsUnquotedSpacesKeepsQuotedOnesAndSkipsEmptyLines) {
  const CsvTable table = parse_csv_text("  a , b\n\n   \n  x  ,\"  y  \"\n\n", "t.csv");
  ASSERT_EQ(table.rows.size(), 1u);
  EXPECT_EQ(table.header[0].text, "a");
  EXPECT_EQ(table.header[1].text, "b");
  EXPECT_EQ(table.rows[0][0].text, "x");
  EXPECT_EQ(table.rows[0][1].text, "  y  ");
  EXPECT_EQ(table.rows[0][0].where.to_string(), "t.csv:4:3");
  EXPECT_EQ(table.rows[0][1].where.to_string(), "t.csv:4:7");
}

TEST(CsvTable, EmptyFieldsAndColumnLookup) {
  const CsvTable table = parse_csv_text("a,b,c\n1,,3\n", "t.csv");
  EXPECT_EQ(table.rows[0][1].text, "");
  EXPECT_EQ(table.column("c"), 2);
  EXPECT_EQ(table.column("z"), -1);
  EXPECT_EQ(table.require_column("b"), 1);
  try {
    table.require_column("scene_b");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(), "t.csv:1:1: key 'scene_b': missing column 'scene_b' in t.csv (columns: 'a', 'b', 'c')");
  }
}

TEST(CsvTable, UnterminatedQuoteIsReportedWhereItStarted) {
  EXPECT_EQ(error_of("a,b\n1,\"open\n2,3\n"),
            "t.csv:2:3: unterminated quoted field: the quote opened here is never closed");
}

TEST(CsvTable, RaggedRow) {
  EXPECT_EQ(error_of("a,b\n1,2\n1,2,3\n"), "t.csv:3:1: ragged row: expected 2 fields (as in the header), found 3");
}

TEST(CsvTable, DuplicateAndEmptyHeaderNames) {
  EXPECT_EQ(error_of("a,b,a\n1,2,3\n"), "t.csv:1:5: key 'a': duplicate column name 'a' (also column 1)");
  EXPECT_EQ(error_of("a,,c\n1,2,3\n"), "t.csv:1:3: empty column name (column 2)");
}

TEST(CsvTable, TextAfterClosingQuoteAndStrayQuote) {
  EXPECT_EQ(error_of("a\n\"x\"y\n"),
            "t.csv:2:4: unexpected character after a closing quote (expected ',' or the end of the line)");
  EXPECT_EQ(error_of("a\nx\"y\n"),
            "t.csv:2:2: quote inside an unquoted field (quote the whole field and double the quote)");
}

TEST(CsvTable, MissingFileIsReportedAtTheReference) {
  test::ScratchDir dir;
  const std::string missing = (dir.path() / "nope.csv").string();
  try {
    read_csv_file(missing, SourceLocation{"exp.toml", 12, 1});
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& error) {
    EXPECT_EQ(std::string(error.what()), "exp.toml:12:1: condition table '" + missing + "': file not found");
  }
}

TEST(CsvTable, ReadsFileWithByteOrderMark) {
  test::ScratchDir dir;
  const std::string path = dir.write("t.csv", "\xEF\xBB\xBFname,scene_a\nx,y\n");
  const CsvTable table = read_csv_file(path, SourceLocation{});
  EXPECT_EQ(table.file, path);
  EXPECT_EQ(table.header[0].text, "name");
  EXPECT_EQ(table.header[0].where.column, 1);
  EXPECT_EQ(table.rows[0][1].text, "y");
}

}  // namespace
}  // namespace glarelab
