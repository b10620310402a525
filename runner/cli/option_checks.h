#pragma once
// Checks for command-line values, applied to the text before CLI11 converts it, so that "-1" never
// wraps to 2^64 - 1 and a refusal names the option, the bounds and the value as typed (exit 2).
// CLI11's own range checks print their bounds with %f ("not in range 0.000000 to 1797693...").
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace glarelab::cli {

// Seeds are stored in the experiment record (TOML) and the sessions table (SQLite), both signed
// 64-bit integers: a seed is a whole number from 0 to 2^63 - 1.
inline constexpr std::int64_t kMaxSeed = INT64_MAX;

// A whole number (digits only, no sign) from `minimum` to `maximum`.
CLI::Validator whole_number_check(std::int64_t minimum, std::int64_t maximum);
// whole_number_check(0, kMaxSeed), named for the message.
CLI::Validator seed_check();
// A finite number (no nan, inf) from `minimum` to `maximum`, `unit` printed after the bounds.
CLI::Validator finite_number_check(double minimum, double maximum, const std::string& unit = {});

}  // namespace glarelab::cli
