#pragma once
// The ConfigError message of loading an experiment file, for tests of what the reader refuses.
#include <string>

#include "protocols/experiment.h"

namespace glarelab::test {

// what() of the ConfigError load_experiment throws for the file at `path`, or "no error".
inline std::string experiment_error(const std::string& path) {
  try {
    load_experiment(path);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace glarelab::test
