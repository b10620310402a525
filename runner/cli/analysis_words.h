#pragma once
// The figures' words for `glarelab analyze`: the [analysis] table each session stored with its
// resolved experiment (sessions.config), read by protocols/analysis_config.h (which analysis/ may
// not include) and handed to the analysis as plain data (analysis/figure_words.h).
#include "analysis/analysis_report.h"

namespace glarelab::cli {

// The words of the first session that stored an [analysis] table; a note in `data` when another
// session stored different words (the first's are used) or a stored table cannot be read.
analysis::FigureWords figure_words_of(analysis::LoadedData& data);

}  // namespace glarelab::cli
