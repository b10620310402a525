#include "protocols/condition_rows.h"

#include <algorithm>
#include <charconv>

#include "core/real_stimulus.h"
#include "core/text_limits.h"
#include "protocols/forced_choice.h"

namespace glarelab {
namespace {

std::string join_quoted(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "'" : ", '") + item + "'";
  return text;
}

// A row whose scene column names a physical object ("real:desk lamp", core/real_stimulus.h): only
// a rating presents one (the observer looks at the object, then answers); the other procedures
// show images side by side, scale a comparison or let the observer adjust one, none of which a
// real object can be. The object must have a name (the instruction names it), and nothing that
// renders an image (glare, perception stages) can apply to it.
void check_real_stimulus(const LocatedRow& located, std::size_t field, const Experiment& experiment) {
  const ConditionRow& row = located.row;
  const auto& [column, scene] = row.fields[field];
  if (experiment.procedure != "rating") {
    const std::string procedure = experiment.procedure == "forced_choice" ? std::string("forced choice")
                                                                           : experiment.procedure;
    throw ConfigError(located.value_where(field), column,
                      "condition '" + row.name() + "' shows a real stimulus ('" + scene + "'), which " + procedure +
                          " cannot present: a real object can only be rated (procedure type = \"rating\"), since " +
                          procedure + " shows, scales or adjusts images");
  }
  if (real_stimulus_object(scene).empty())
    throw ConfigError(located.value_where(field), column,
                      "condition '" + row.name() + "': '" + scene +
                          "' names no object; write the object after 'real:', e.g. \"real:desk lamp\"");
  for (std::size_t f = 0; f < row.fields.size(); ++f) {
    const auto& [key, value] = row.fields[f];
    const bool renders = (key == "glare" && !value.empty() && value != "control") ||
                         (key == "perception" && !value.empty() && value != "none") ||
                         (key == "glare_model" && !value.empty()) || (key == "glare_gain" && !value.empty());
    if (renders)
      throw ConfigError(located.value_where(f), key,
                        "condition '" + row.name() + "' shows a real stimulus ('" + scene + "'): no image is rendered, "
                            "so '" + key + " = " + value + "' cannot apply (leave it empty" +
                            (key == "glare" ? ", or control" : key == "perception" ? ", or none" : "") + ")");
  }
}

// Every row names an existing scene in each of `columns` (forced choice: scene_a and scene_b;
// staircase and QUEST: reference and comparison).
void check_scene_columns(const std::vector<LocatedRow>& rows, const Experiment& experiment,
                         const std::optional<CsvTable>& csv, const std::vector<std::string>& columns) {
  std::vector<std::string> scene_names;
  for (const auto& entry : experiment.scenes) scene_names.push_back(entry.first);
  for (const std::string& column : columns) {
    if (csv) csv->require_column(column);
  }
  const std::string needs = (experiment.procedure == "forced_choice" ? std::string("forced choice")
                                                                      : experiment.procedure) +
                            " needs " + columns[0] + (columns.size() > 1 ? " and " + columns[1] : std::string());
  for (const LocatedRow& located : rows) {
    const ConditionRow& row = located.row;
    for (const std::string& column : columns) {
      std::size_t f = 0;
      while (f < row.fields.size() && row.fields[f].first != column) ++f;
      if (f == row.fields.size()) {
        throw ConfigError(row.where, column, "condition row " + std::to_string(row.number) +
                                                 " has no '" + column + "' (" + needs + ")");
      }
      const std::string& scene = row.fields[f].second;
      if (is_real_stimulus(scene)) {
        check_real_stimulus(located, f, experiment);
        continue;
      }
      if (experiment.scenes.count(scene) == 0) {
        throw ConfigError(located.value_where(f), column,
                          "unknown scene '" + shortened_value(scene) + "' (scenes in [scenes]: " + join_quoted(scene_names) + ")");
      }
    }
  }
}

// Forced choice shows the scenes named in columns scene_a and scene_b of every row.
void check_forced_choice_rows(const std::vector<LocatedRow>& rows, const Experiment& experiment,
                              const std::optional<CsvTable>& csv) {
  for (const LocatedRow& located : rows) {
    const ConditionRow& row = located.row;
    for (std::size_t f = 0; f < row.fields.size(); ++f) {
      const std::string& column = row.fields[f].first;
      const std::vector<std::string>& reserved = forced_choice_positions(experiment.forced_choice);
      if (std::find(reserved.begin(), reserved.end(), column) != reserved.end()) {
        throw ConfigError(located.key_where(f), column,
                          "column name '" + column + "' is reserved (forced-choice trials record the scene "
                          "shown at each position under '" + reserved[0] + "' and '" + reserved[1] + "')");
      }
    }
  }
  check_scene_columns(rows, experiment, csv, {"scene_a", "scene_b"});
}

// A rating shows the scene named in column scene of every row (an image, or a real object). Its
// trials record the category rated and, for a real object, "stimulus": "real" beside the row's
// columns in trials.condition: a row's own column of either name would be recorded twice.
void check_rating_rows(const std::vector<LocatedRow>& rows, const Experiment& experiment,
                       const std::optional<CsvTable>& csv) {
  for (const LocatedRow& located : rows)
    for (std::size_t f = 0; f < located.row.fields.size(); ++f) {
      const std::string& column = located.row.fields[f].first;
      if (column == "category" || column == "stimulus")
        throw ConfigError(located.key_where(f), column,
                          "column name '" + column + "' is reserved (rating trials record the category rated under "
                          "'category' and a real stimulus under 'stimulus')");
    }
  check_scene_columns(rows, experiment, csv, {"scene"});
}

}  // namespace

SourceLocation LocatedRow::value_where(std::size_t field) const {
  return SourceLocation{*value_file, value_places[field].first, value_places[field].second};
}

void rows_from_csv_file(const std::string& path, const SourceLocation& referenced_from, ConditionSource& source) {
  const auto file = std::make_shared<const std::string>(path);
  std::shared_ptr<const std::vector<SourceLocation>> keys;
  source.csv = read_csv_file_rows(path, referenced_from, [&](const CsvTable& table, std::vector<CsvField>& cells) {
    if (!keys) {  // every row shares the header's places
      auto header = std::make_shared<std::vector<SourceLocation>>();
      for (const CsvCell& cell : table.header) header->push_back(cell.where);
      keys = std::move(header);
    }
    LocatedRow& located = source.rows.emplace_back();
    located.row.where = SourceLocation{path, cells.front().line, 1};
    located.row.fields.reserve(cells.size());
    located.value_places.reserve(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      located.row.fields.emplace_back(table.header[c].text, std::move(cells[c].text));
      located.value_places.emplace_back(cells[c].line, cells[c].column);
    }
    located.value_file = file;
    located.key_places = keys;
  });
}

std::vector<LocatedRow> rows_from_toml(const toml::array& array, const std::string& key, const std::string& file) {
  std::vector<LocatedRow> rows;
  const auto value_file = std::make_shared<const std::string>(file);
  for (std::size_t i = 0; i < array.size(); ++i) {
    const toml::node& element = *array.get(i);
    const std::string row_key = key + "[" + std::to_string(i) + "]";
    if (!element.is_table()) {
      throw ConfigError(to_location(element.source(), file), row_key,
                        "expected a table such as { name = \"...\", scene_a = \"...\", scene_b = \"...\" }, found " +
                            describe_toml_type(element));
    }
    const toml::table& table = *element.as_table();
    // toml::table keeps keys sorted; the columns' meaning does not depend on order, but the
    // condition_json written with every trial should read in the order the experimenter wrote.
    std::vector<const toml::key*> keys;
    for (const auto& entry : table) keys.push_back(&entry.first);
    std::sort(keys.begin(), keys.end(),
              [](const toml::key* a, const toml::key* b) { return a->source().begin < b->source().begin; });
    LocatedRow located;
    located.row.where = to_location(table.source(), file);
    located.value_file = value_file;
    auto key_places = std::make_shared<std::vector<SourceLocation>>();
    for (const toml::key* column : keys) {
      const toml::node& value = *table.get(column->str());
      const std::string cell_key = row_key + "." + std::string(column->str());
      std::string text;
      // Condition values are text (as in a CSV table); numbers and booleans are accepted and kept
      // in their TOML spelling so `contrast = 0.5` needs no quotes.
      if (value.is_string()) {
        text = value.as_string()->get();
      } else if (value.is_integer()) {
        text = std::to_string(value.as_integer()->get());
      } else if (value.is_floating_point()) {
        // Shortest text that reads back as the same double, as the experimenter likely wrote it.
        char buffer[64];
        const auto written = std::to_chars(buffer, buffer + sizeof buffer, value.as_floating_point()->get());
        text.assign(buffer, written.ptr);
      } else if (value.is_boolean()) {
        text = value.as_boolean()->get() ? "true" : "false";
      } else {
        throw ConfigError(to_location(value.source(), file), cell_key,
                          "expected a string, number or boolean, found " + describe_toml_type(value));
      }
      located.row.fields.emplace_back(std::string(column->str()), std::move(text));
      const SourceLocation value_where = to_location(value.source(), file);
      located.value_places.emplace_back(value_where.line, value_where.column);
      key_places->push_back(to_location(column->source(), file));
    }
    located.key_places = std::move(key_places);
    rows.push_back(std::move(located));
  }
  return rows;
}

ConditionSource generated_conditions(TableReader& top, const GeneratedDesign& generated, Experiment& experiment) {
  for (const char* section : {"conditions", "blocks"}) {
    if (top.node(section) != nullptr)
      top.fail_at_key(section, section == std::string("blocks")
                                   ? "design = \"all_pairs\" generates the blocks (one per instruction); remove "
                                     "[[blocks]] or the design key at " + generated.where.to_string()
                                   : "design = \"all_pairs\" generates the condition rows; remove [conditions] or "
                                     "the design key at " + generated.where.to_string());
  }
  ConditionSource source;
  for (const ConditionRow& row : generated.rows) {
    LocatedRow located;
    located.row = row;
    located.value_file = std::make_shared<const std::string>(generated.where.file);
    located.value_places.assign(row.fields.size(), {generated.where.line, generated.where.column});
    located.key_places = std::make_shared<const std::vector<SourceLocation>>(row.fields.size(), generated.where);
    source.rows.push_back(std::move(located));
  }
  experiment.design.blocks = generated.blocks;
  return source;
}

void check_condition_scenes(const ConditionSource& conditions, const Experiment& experiment) {
  if (experiment.procedure == "forced_choice") check_forced_choice_rows(conditions.rows, experiment, conditions.csv);
  else if (experiment.procedure == "rating") check_rating_rows(conditions.rows, experiment, conditions.csv);
  else if (experiment.procedure == "adjustment")
    check_scene_columns(conditions.rows, experiment, conditions.csv, {"target", "comparison"});
  else check_scene_columns(conditions.rows, experiment, conditions.csv, {"reference", "comparison"});
}

ConfigError at_value_cell(const ConfigError& error, const LocatedRow& located) {
  const SourceLocation& row = located.row.where;
  if (error.where().file != row.file || error.where().line != row.line || error.where().column != row.column)
    return error;
  const std::string& key = error.key();
  for (std::size_t f = 0; f < located.row.fields.size() && f < located.value_places.size(); ++f) {
    const std::string& column = located.row.fields[f].first;
    if (key == column || (key.size() > column.size() + 1 && key.ends_with(" " + column)))
      return ConfigError(located.value_where(f), key, error.message());
  }
  return error;
}

}  // namespace glarelab
