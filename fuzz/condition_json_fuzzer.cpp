// Fuzz target: the condition JSON of a stored trial as analyze reads it (analysis/loaded_database.h,
// parse_condition_json). Expected outcome for bad input: std::invalid_argument ("not JSON", "not a
// JSON object", nested deeper than the bound of core/text_limits.h). An object that parses keeps
// its promises: its keys are distinct, and a string value of a key comes back as that string.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>

#include "analysis/loaded_database.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glarelab;
  analysis::ConditionFields fields;
  try {
    fields = analysis::parse_condition_json(fuzz::as_text(data, size));
  } catch (const std::invalid_argument&) {
    return 0;
  }
  std::set<std::string> keys;
  for (const auto& [key, value] : fields) {
    if (!keys.insert(key).second) {
      std::fprintf(stderr, "key '%s' read twice\n", key.c_str());
      std::abort();
    }
  }
  return 0;
}
