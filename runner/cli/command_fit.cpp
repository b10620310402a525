// `glarelab fit DATA.csv --options OPTIONS.json --out RESULT.json`: a psignifit 4 fit of one
// table of blocks, with psignifit's option and result names (docs/ANALYSIS.md, "Psychometric
// fits, psignifit 4"), so a fit can be checked against psignifit itself.
#include <filesystem>
#include <iostream>
#include <memory>

#include "analysis/psignifit_fit.h"
#include "analysis/psignifit_io.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "runner/cli/commands.h"

namespace glarelab::cli {

namespace {

struct FitArguments {
  std::string data;
  std::string options;
  std::string out;
};

const char* const kParameterNames[analysis::kPsignifitParameters] = {"threshold", "width", "lambda", "gamma", "eta"};

int run_fit(const FitArguments& arguments) {
  const std::vector<analysis::PsignifitBlock> data = analysis::read_psignifit_data(arguments.data);
  const analysis::PsignifitOptions options =
      arguments.options.empty() ? analysis::PsignifitOptions{} : analysis::read_psignifit_options(arguments.options);
  const analysis::PsignifitResult result = analysis::psignifit_fit(data, options);
  const std::string text = analysis::psignifit_result_json(result);
  if (arguments.out.empty() || arguments.out == "-") {
    std::cout << text;
    return kExitOk;
  }
  // Beside and renamed into place (core/atomic_file.h); a link standing at --out is refused.
  refuse_symbolic_link(arguments.out, "--out");
  write_file_atomically(arguments.out, text);
  // A short summary for the terminal; the file holds everything.
  std::cout << arguments.out << ": " << analysis::psignifit_sigmoid_name(result.options.sigmoid) << " fit of "
            << result.blocks.size() << " block(s), " << (result.options.estimate_map ? "MAP" : "posterior mean") << "\n";
  for (int p = 0; p < analysis::kPsignifitParameters; ++p) {
    std::cout << "  " << kParameterNames[p] << " " << result.fit[p];
    if (!result.intervals[p].empty())
      std::cout << " [" << result.intervals[p][0].low << ", " << result.intervals[p][0].high << "] at "
                << result.options.credibility[0];
    std::cout << "\n";
  }
  if (analysis::psignifit_log_space(result.options.sigmoid))
    std::cout << "  (threshold and width on natural-log levels; threshold level "
              << analysis::psignifit_threshold(result.options, result.fit, result.options.thresh_pc) << ")\n";
  std::cout << "  deviance " << result.deviance << "\n";
  return kExitOk;
}

}  // namespace

Action add_fit_command(CLI::App& app) {
  auto arguments = std::make_shared<FitArguments>();
  CLI::App* fit = app.add_subcommand("fit", "Bayesian psychometric fit of a level,correct,trials table as psignifit 4 makes it");
  fit->add_option("data", arguments->data, "Data table (CSV rows level,correct,trials)")->required();
  fit->add_option("--options", arguments->options, "psignifit options (JSON: expType, sigmoidName, threshPC, ...)");
  fit->add_option("--out", arguments->out, "Result file (JSON: Fit, meanFit, conf_Intervals, deviance, logPmax); - or none: stdout");
  return [=]() { return report_errors([&]() { return run_fit(*arguments); }); };
}

}  // namespace glarelab::cli
