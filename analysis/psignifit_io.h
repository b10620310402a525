#pragma once
// The files of `glarelab fit` (docs/ANALYSIS.md, "Psychometric fits, psignifit 4"): a data table
// of blocks `level,correct,trials`, an options file in JSON with psignifit 4's option names, and
// a result file in JSON with psignifit's field names (Fit, meanFit, conf_Intervals, deviance,
// logPmax, ...), so that a fit can be set beside psignifit's own. Errors name the file, the line
// and column, and the key (core/errors.h ConfigError); unknown option names are errors.
#include <string>
#include <vector>

#include "analysis/psignifit_fit.h"

namespace glarelab::analysis {

// Reads `level,correct,trials` rows (a first row naming those columns is allowed; blank lines and
// lines starting with # are skipped).
std::vector<PsignifitBlock> read_psignifit_data(const std::string& path);
std::vector<PsignifitBlock> parse_psignifit_data(const std::string& text, const std::string& file_name);

// The option names read, in the order the documentation lists them.
const std::vector<std::string>& psignifit_option_names();

PsignifitOptions read_psignifit_options(const std::string& path);
PsignifitOptions parse_psignifit_options(const std::string& text, const std::string& file_name);

// The result as JSON text (psignifit's field names and parameter order).
std::string psignifit_result_json(const PsignifitResult& result);

}  // namespace glarelab::analysis
