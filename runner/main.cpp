// glarelab: psychophysics experiment runner and stimulus presenter for glare studies.
#include <CLI/CLI.hpp>

#include <iostream>

#include "runner/cli/commands.h"
#include "runner/software_version.h"

int main(int argc, char** argv) {
  CLI::App app{"glarelab: psychophysics experiments with HDR stimuli and glare"};
  app.set_version_flag("--version", std::string("glarelab ") + glarelab::software_version());
  app.require_subcommand(1);
  auto run_action = glarelab::cli::add_run_command(app);
  auto validate_action = glarelab::cli::add_validate_command(app);
  auto devices_action = glarelab::cli::add_devices_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // Usage errors are bad input (exit 2), like a broken experiment file.
    const int code = app.exit(error);
    return code == 0 ? 0 : 2;
  }
  if (app.got_subcommand("run")) return run_action();
  if (app.got_subcommand("validate")) return validate_action();
  if (app.got_subcommand("devices")) return devices_action();
  return 2;
}
