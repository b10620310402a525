// glarelab eye-trace: the simulated eye's state over time as CSV (pupil, accommodation, vitreous
// angle, blinks), for inspecting the dynamic eye model without computing any glare.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "glare/eye/eye_model.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "runner/cli/commands.h"
#include "protocols/glare_eye_file.h"
#include "runner/cli/option_checks.h"

namespace glarelab::cli {

namespace {

struct EyeTraceOptions {
  double duration_s = 10.0;
  double rate_hz = 60.0;
  double field_luminance_cd_m2 = 100.0;
  std::uint64_t seed = 1;
  std::string mode = "dynamic";
  double static_time_s = 0.0;
  double squint_closure = 0.0;
  bool squint_given = false;  // --squint replaces [glare.eye]'s squint_closure only when given
  std::string eye_from;       // an experiment file whose [glare.eye] sets the eye (protocols/glare_eye_file.h)
  std::string out;
};

int write_eye_trace(const EyeTraceOptions& options) {
  const SourceLocation where{"eye-trace", 0, 0};
  if (!(options.duration_s > 0.0) || !std::isfinite(options.duration_s))
    throw ConfigError(where, "--duration-s", "must be a positive number of seconds");
  if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz))
    throw ConfigError(where, "--rate-hz", "must be a positive rate");
  if (options.duration_s * options.rate_hz > 1e7)
    throw ConfigError(where, "--rate-hz", "more than 10 million samples requested");
  EyeParameters parameters;
  if (!options.eye_from.empty()) read_glare_eye_file(options.eye_from, parameters);
  parameters.mode = parse_glare_mode(options.mode);
  parameters.static_time_s = options.static_time_s;
  parameters.initial_field_luminance_cd_m2 = options.field_luminance_cd_m2;
  if (options.squint_given || options.eye_from.empty()) parameters.squint_closure = options.squint_closure;
  validate(parameters, "eye-trace options");
  const EyeModel eye(parameters, options.seed);

  // Written beside --out and renamed into place (a run stopped half way leaves no half a trace);
  // a link at --out is refused, not written through.
  refuse_symbolic_link(options.out, "--out");
  AtomicFile file(options.out);
  std::ostream& out = file.stream();
  out << "time_s,field_luminance_cd_m2,mean_pupil_diameter_mm,pupil_diameter_mm,accommodation_dioptres,"
         "defocus_dioptres,lens_equator_displacement_um,vitreous_angle_deg,blink_closure,lid_closure,"
         "gratings_in_pupil\n";
  const auto samples = static_cast<long long>(std::floor(options.duration_s * options.rate_hz + 1e-9)) + 1;
  char row[512];
  for (long long k = 0; k < samples; ++k) {
    const double t = static_cast<double>(k) / options.rate_hz;
    const EyeState s = eye.state_at(t);
    std::snprintf(row, sizeof row, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", t,
                  s.field_luminance_cd_m2, s.mean_pupil_diameter_mm, s.pupil_diameter_mm, s.accommodation_dioptres,
                  s.defocus_dioptres, s.lens_equator_displacement_mm * 1000.0,
                  s.vitreous_angle_rad * 180.0 / 3.14159265358979323846, s.blink_closure, s.lid_closure,
                  s.gratings_in_pupil ? 1 : 0);
    out << row;
  }
  file.commit();
  std::cout << "eye-trace: " << samples << " samples over " << options.duration_s << " s at " << options.rate_hz
            << " Hz, " << to_string(parameters.mode) << " eye, seed " << options.seed
            << (options.eye_from.empty() ? std::string() : ", [glare.eye] of " + options.eye_from) << " -> " << options.out
            << "\n";
  return 0;
}

}  // namespace

Action add_eye_trace_command(CLI::App& app) {
  auto options = std::make_shared<EyeTraceOptions>();
  CLI::App* command = app.add_subcommand("eye-trace", "Write the simulated eye's pupil, accommodation, vitreous and "
                                                      "blink state over time as CSV");
  // Every number is checked here, so a refusal names its flag (exit 2) before the CSV is opened.
  command->add_option("--duration-s", options->duration_s, "Length of the trace in seconds, at most 86400 (24 h)")
      ->check(eye_model_time_s())
      ->capture_default_str();
  command->add_option("--rate-hz", options->rate_hz, "Samples per second")->check(finite_positive_number("Hz"))->capture_default_str();
  command->add_option("--field-luminance-cd-m2", options->field_luminance_cd_m2, "Constant field luminance (cd/m2)")
      ->check(finite_positive_number("cd/m2"))
      ->capture_default_str();
  command->add_option("--seed", options->seed, "Seed of the eye model")->check(seed_check())->capture_default_str();
  command->add_option("--mode", options->mode, "dynamic, static or control")->capture_default_str();
  command->add_option("--static-time-s", options->static_time_s, "Instant a static eye is frozen at (s), at most 86400 (24 h)")
      ->check(eye_model_time_s())
      ->capture_default_str();
  CLI::Option* squint = command->add_option("--squint", options->squint_closure,
                                             "Constant lid closure 0..1 (replaces --eye-from's squint_closure)")
                            ->check(finite_number_in(0.0, 1.0, ""))
                            ->capture_default_str();
  command->add_option("--eye-from", options->eye_from,
                      "Experiment file whose [glare.eye] table sets the eye model (docs/EXPERIMENT_FILES.md)");
  command->add_option("--out", options->out, "Output CSV file")->required();
  return [=]() {
    options->squint_given = squint->count() > 0;
    return report_errors([&]() { return write_eye_trace(*options); });
  };
}

}  // namespace glarelab::cli
