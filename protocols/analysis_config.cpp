// [analysis]: the report's words (protocols/analysis_config.h), read through TableReader so a
// misspelt key stops the run (protocols/toml_table_reader.h).
#include "protocols/analysis_config.h"

#include <optional>

#include "core/errors.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {
namespace {

// A text of at most 200 characters that is not empty: an axis label a figure can print.
std::string read_words(TableReader& reader, std::string_view key) {
  const std::optional<std::string> value = reader.string(key);
  if (!value) return {};
  if (value->empty()) reader.fail(key, "must not be empty (leave the key out for the report's own words)");
  if (value->size() > 200) reader.fail(key, "must be at most 200 characters (an axis label or a name)");
  return *value;
}

AnalysisLabels read_labels(TableReader& reader) {
  AnalysisLabels labels;
  labels.graded_label = read_words(reader, "graded_label");
  labels.graded_unit = read_words(reader, "graded_unit");
  labels.answer_label = read_words(reader, "answer_label");
  labels.group_label = read_words(reader, "group_label");
  if (const toml::table* names = reader.table("names")) {
    TableReader name_reader(*names, reader.key_path("names"), reader.file());
    name_reader.consume_all();  // the keys are the experiment's own condition, group and track names
    for (const auto& [key, node] : *names) {
      const std::string name(key.str());
      if (name.empty()) name_reader.fail_at_key(name, "names must not be empty");
      labels.names.emplace_back(name, read_words(name_reader, name));
    }
  }
  reader.report_unused();
  return labels;
}

}  // namespace

AnalysisLabels read_analysis_section(TableReader& top) {
  const toml::table* table = top.table("analysis");
  if (table == nullptr) return {};
  TableReader reader(*table, "analysis", top.file());
  return read_labels(reader);
}

toml::table analysis_section_toml(const AnalysisLabels& labels) {
  toml::table table;
  for (const auto& [key, value] : {std::pair<const char*, const std::string*>{"graded_label", &labels.graded_label},
                                   {"graded_unit", &labels.graded_unit},
                                   {"answer_label", &labels.answer_label},
                                   {"group_label", &labels.group_label}})
    if (!value->empty()) table.insert(key, *value);
  if (!labels.names.empty()) {
    toml::table names;
    for (const auto& [name, display] : labels.names) names.insert(name, display);
    table.insert("names", std::move(names));
  }
  return table;
}

AnalysisLabels stored_analysis_labels(const std::string& config_toml, const std::string& origin) {
  toml::table root;
  try {
    root = toml::parse(config_toml, origin);
  } catch (const toml::parse_error&) {
    return {};  // not TOML (a session from before stored configs): no words stored
  }
  const toml::table* table = root["analysis"].as_table();
  if (table == nullptr) return {};
  TableReader reader(*table, "analysis", origin);
  return read_labels(reader);
}

}  // namespace glarelab
