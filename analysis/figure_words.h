#pragma once
// The words a report's figures print: axis labels, units and display names of conditions, from
// the experiment file's `[analysis]` table (docs/EXPERIMENT_FILES.md; read and checked by
// protocols/analysis_config.h, handed over by the runner as plain data), each with a default built
// from the data when the table does not give it. A journal prints what a reader understands
// ("glare mode", "No glare"), not the column names a design file uses ("glare_a", "control").
#include <map>
#include <string>

namespace glarelab::analysis {

struct FigureWords {
  std::string graded_label;  // the graded variable's axis words; empty: built from the column's name
  std::string graded_unit;   // its unit; empty: none printed
  std::string answer_label;  // the y axis of graded choice; empty: "proportion choosing scene_b"
  std::string group_label;   // what the groups are (the legend's heading words); empty: "glare"
  std::map<std::string, std::string> names;  // display name per condition, group or track name

  // The display name of `name`: its entry in `names`, else `name` itself.
  const std::string& display(const std::string& name) const;
};

// A column's name as words: underscores to spaces ("luminance_ratio" -> "luminance ratio").
std::string column_words(const std::string& column);

}  // namespace glarelab::analysis
