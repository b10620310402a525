#include "runner/cli/analysis_words.h"

#include <optional>
#include <string>

#include "core/errors.h"
#include "protocols/analysis_config.h"

namespace glarelab::cli {

analysis::FigureWords figure_words_of(analysis::LoadedData& data) {
  analysis::FigureWords words;
  std::optional<AnalysisLabels> first;
  std::string first_label;
  for (const analysis::LoadedSession& session : data.sessions) {
    AnalysisLabels labels;
    try {
      labels = stored_analysis_labels(session.record.config, session.label + " sessions.config");
    } catch (const ConfigError& error) {
      data.notes.push_back(std::string("[analysis] of ") + session.label + " not used: " + error.what());
      continue;
    }
    if (labels.empty()) continue;
    if (!first) {
      first = labels;
      first_label = session.label;
    } else if (labels.graded_label != first->graded_label || labels.graded_unit != first->graded_unit ||
               labels.answer_label != first->answer_label || labels.group_label != first->group_label ||
               labels.names != first->names) {
      data.notes.push_back("the [analysis] words of " + session.label + " differ from those of " + first_label +
                           "; the figures use the latter's");
    }
  }
  if (!first) return words;
  words.graded_label = first->graded_label;
  words.graded_unit = first->graded_unit;
  words.answer_label = first->answer_label;
  words.group_label = first->group_label;
  for (const auto& [name, display] : first->names) words.names[name] = display;
  return words;
}

}  // namespace glarelab::cli
