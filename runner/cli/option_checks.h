#pragma once
// Checks of number and file options shared by the subcommands. CLI11's own Range lets NaN through
// (every comparison with NaN is false) and reports infinities as "not in range 0.000000 to 1.79e308":
// these say what the option must be and what was found, and CLI11 prefixes the option's name
// ("--time-s: must be ..."), so every refusal names the flag and ends the program with exit 2.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <initializer_list>
#include <string>

#include "core/spelling.h"
#include "glare/refraction/dioptric_power.h"

namespace glarelab::cli {

// A finite number (no nan, no inf).
CLI::Validator finite_number();
// A finite number in [low, high]; `unit` follows the bounds in the message ("mm", "s"; may be empty).
CLI::Validator finite_number_in(double low, double high, const std::string& unit);
// A finite number > 0.
CLI::Validator finite_positive_number(const std::string& unit);
// A time the eye model answers for: finite, from 0 to kMaxEyeModelTime_s (24 h, glare/eye/eye_parameters.h).
CLI::Validator eye_model_time_s();
// A file name ending in one of `extensions` (".exr", ".png"; compared without case).
CLI::Validator file_extension_in(std::initializer_list<const char*> extensions, const std::string& what);

// An option whose text is one of Enum's words (core/spelling.h), parsed into `value` where the flag
// is read: another text is refused naming the flag and the words it takes ("--backend: unknown value
// 'cuda' (supported: 'auto', 'cpu', 'gl')"). Help shows the words ("{auto,cpu,gl}") and `value`'s
// word as the default.
template <typename Enum>
CLI::Option* add_choice_option(CLI::App* command, const std::string& name, Enum& value, const std::string& description) {
  CLI::Option* option = command->add_option_function<std::string>(
      name, [&value](const std::string& text) { value = *parse_spelling<Enum>(text); }, description);
  std::string words;
  for (const Spelling<Enum>& entry : spellings(Enum{})) words += (words.empty() ? "{" : ",") + std::string(entry.text);
  option->check(CLI::Validator(
      [](const std::string& text) {
        return parse_spelling<Enum>(text) ? std::string()
                                          : "unknown value '" + text + "' (supported: " + spelling_list<Enum>() + ")";
      },
      words + "}"));
  option->default_str(std::string(spelling(value)));
  return option;
}

// Sphero-cylinders on the command line (prescriptions, spectacle lenses): sphere and cylinder in
// dioptres, axis in TABO degrees. The bounds take every prescription a clinic writes.
inline constexpr double kMaxSphereDioptres = 30.0;    // |sphere|
inline constexpr double kMaxCylinderDioptres = 15.0;  // |cylinder|
inline constexpr double kMaxAxisDeg = 180.0;          // axes from 0 to 180 (180 is 0)

// A plus-cylinder prescription (C > 0) transposed to the minus-cylinder form glarelab computes with:
// (S + C, -C, A + 90 wrapped into [0, 180)), the same lens. Minus cylinders pass unchanged.
SpheroCylinder minus_cylinder_form(const SpheroCylinder& prescription);

// "S,C,A" (sphere, cylinder, axis): three finite numbers within the bounds above, as written (a
// positive cylinder is kept; minus_cylinder_form transposes it). Throws std::invalid_argument with
// the reason, which does not name the option (CLI11 prefixes it).
SpheroCylinder parse_sphero_cylinder(const std::string& text);
// The validator of a "S,C,A" option.
CLI::Validator sphero_cylinder_check();

// Seeds are stored in the experiment record (TOML) and the sessions table (SQLite), both signed
// 64-bit integers: a seed is a whole number from 0 to 2^63 - 1. Checked on the text, so "-1" never
// wraps to 2^64 - 1.
inline constexpr std::int64_t kMaxSeed = INT64_MAX;

// A whole number (digits only, no sign) from `minimum` to `maximum`.
CLI::Validator whole_number_check(std::int64_t minimum, std::int64_t maximum);
// whole_number_check(0, kMaxSeed).
CLI::Validator seed_check();

// Participant numbers pick a block order (counterbalancing cycles through them); a million is far
// beyond any study and keeps the number readable in file names and logs.
constexpr std::int64_t kMaxParticipantNumber = 1000000;

}  // namespace glarelab::cli
