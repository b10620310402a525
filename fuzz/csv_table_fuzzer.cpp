// Fuzz target: RFC 4180 condition tables (protocols/csv_table.h). Expected outcome for bad input:
// ConfigError naming file, line and column. A table that parses must keep its own promises:
// every row has as many cells as the header, and each header name is found by column().
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "fuzz/fuzz_support.h"
#include "protocols/csv_table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  CsvTable table;
  try {
    table = parse_csv_text(fuzz::as_text(data, size), "fuzz.csv");
  } catch (const ConfigError&) {
    return 0;
  }
  for (const auto& row : table.rows) {
    if (row.size() != table.header.size()) {
      std::fprintf(stderr, "row of %zu cells under a header of %zu\n", row.size(), table.header.size());
      std::abort();
    }
  }
  for (std::size_t i = 0; i < table.header.size(); ++i) {
    if (table.column(table.header[i].text) != static_cast<int>(i)) {
      std::fprintf(stderr, "column('%s') is not %zu\n", table.header[i].text.c_str(), i);
      std::abort();
    }
  }
  try {
    (void)table.require_column("a column no table has \x01");
  } catch (const ConfigError&) {
  }
  return 0;
}
