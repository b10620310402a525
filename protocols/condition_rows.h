#pragma once
// The condition rows of an experiment file: those of [conditions] (a CSV table, or inline
// [[conditions.rows]]) or those design = "all_pairs" generates, each value with where it was
// written, and their checks against the scenes the procedure shows (protocols/experiment_file.cpp
// reads the rest of the file).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "core/errors.h"
#include "protocols/csv_table.h"
#include "protocols/experiment.h"
#include "protocols/pair_design.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

// A condition row together with where each of its values was written, for error messages. A
// table of a million rows is held here once: each value's place is two numbers, its file and the
// keys' places are shared by every row that has them.
struct LocatedRow {
  ConditionRow row;
  std::shared_ptr<const std::string> value_file;  // the file the values were written in
  std::vector<std::pair<int, int>> value_places;  // line and column of each value, parallel to row.fields
  std::shared_ptr<const std::vector<SourceLocation>> key_places;  // the CSV header cell or the TOML key

  SourceLocation value_where(std::size_t field) const;
  const SourceLocation& key_where(std::size_t field) const { return (*key_places)[field]; }
};

struct ConditionSource {
  std::vector<LocatedRow> rows;
  std::optional<CsvTable> csv;  // when the rows came from a CSV file: its header (the rows are above)
};

// The rows of the CSV condition table at `path`, in file order, read row by row (the table's header
// goes to `source.csv`).
void rows_from_csv_file(const std::string& path, const SourceLocation& referenced_from, ConditionSource& source);

// The rows of [[conditions.rows]] (`key` its dotted name), each row's columns in the order written.
std::vector<LocatedRow> rows_from_toml(const toml::array& array, const std::string& key, const std::string& file);

// design = "all_pairs" writes the condition rows and blocks itself: a [conditions] table or
// [[blocks]] beside it would be a second, conflicting design.
ConditionSource generated_conditions(TableReader& top, const GeneratedDesign& generated, Experiment& experiment);

// Every row names the scenes its procedure shows, in existing [scenes] or as a real object a
// rating can present (forced choice: scene_a and scene_b; rating: scene; adjustment: target and
// comparison; staircase, QUEST, QUEST+ and Psi: reference and comparison), and uses no column the
// procedure records under its own name.
void check_condition_scenes(const ConditionSource& conditions, const Experiment& experiment);

// A ConfigError about one of a row's values that was raised where only the row was known (its
// first cell): moved to the value's own cell when its key ends with one of the row's columns
// ("condition 'c' glare_a"), so an editor jumps to the bad cell; any other error as it was.
ConfigError at_value_cell(const ConfigError& error, const LocatedRow& located);

}  // namespace glarelab
