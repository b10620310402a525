#pragma once
// The [analysis] table of an experiment file: the words `glarelab analyze` prints on the report's
// figures (axis labels, units, display names of conditions and groups), so the figures a journal
// prints say "glare mode" and "no glare" rather than a design file's column names
// (docs/EXPERIMENT_FILES.md, `[analysis]`). Every key is optional; without one the report builds
// its own words from the data. Read strictly (unknown keys and empty texts are ConfigErrors naming
// file:line:column and the key), stored with the session in the resolved experiment, and read
// back from sessions.config by the analysis command.
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace glarelab {

class TableReader;

struct AnalysisLabels {
  std::string graded_label;  // the graded variable's axis words (forced choice with a graded variable; staircases)
  std::string graded_unit;   // its unit, printed in parentheses after the words
  std::string answer_label;  // the y axis of the graded choice figure: what a proportion counts
  std::string group_label;   // what the groups are, e.g. "glare mode"
  std::vector<std::pair<std::string, std::string>> names;  // [analysis.names]: name in the data -> display name
  bool empty() const {
    return graded_label.empty() && graded_unit.empty() && answer_label.empty() && group_label.empty() && names.empty();
  }
};

// Reads [analysis] of the experiment file's root (nothing when absent).
AnalysisLabels read_analysis_section(TableReader& top);
// The table resolved_config_toml writes (only the keys given).
toml::table analysis_section_toml(const AnalysisLabels& labels);
// [analysis] of a stored resolved experiment (sessions.config); empty labels when the text has
// none. `origin` names the text in errors (a stored table is read as strictly as a file).
AnalysisLabels stored_analysis_labels(const std::string& config_toml, const std::string& origin);

}  // namespace glarelab
