// Fuzz target: the experiment file and every table reader behind load_experiment.
// Input: the experiment's TOML, optionally followed by a line "#--- conditions.csv ---" and the
// condition table that `[conditions] file = "conditions.csv"` reads, both written next to each
// other in a scratch folder. Expected outcome for bad input: ConfigError (file:line:column), the
// only error load_experiment documents. Anything else (another exception, a crash, a sanitizer
// report) is a finding. An experiment that loads must also survive its own resolved TOML
// (parse_experiment_text(resolved_config_toml(e)) gives back e, protocols/experiment.h): a
// resolved config that does not parse back would make a stored session impossible to resume.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/errors.h"
#include "fuzz/fuzz_support.h"
#include "protocols/experiment.h"

namespace {
constexpr std::string_view kCsvMarker = "\n#--- conditions.csv ---\n";
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  const fuzz::ScratchFolder& folder = fuzz::ScratchFolder::instance();
  const std::string input = fuzz::as_text(data, size);
  const std::size_t marker = input.find(kCsvMarker);
  std::string toml_path;
  if (marker == std::string::npos) {
    toml_path = folder.write("experiment.toml", input);
    folder.remove("conditions.csv");  // a reference to it must then be refused as missing
  } else {
    toml_path = folder.write("experiment.toml", std::string_view(input).substr(0, marker));
    folder.write("conditions.csv", std::string_view(input).substr(marker + kCsvMarker.size()));
  }
  Experiment experiment;
  try {
    experiment = load_experiment(toml_path);
  } catch (const ConfigError&) {
    return 0;  // refused with file:line:column: the expected outcome for bad input
  }
  const std::string resolved = resolved_config_toml(experiment);
  try {
    (void)parse_experiment_text(resolved, "resolved.toml", folder.path().string());
  } catch (const ConfigError& error) {
    std::fprintf(stderr, "resolved config of a loaded experiment does not load again: %s\n--- resolved ---\n%s\n",
                 error.what(), resolved.c_str());
    std::abort();
  }
  return 0;
}
