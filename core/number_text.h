#pragma once
// Numbers in messages: the shortest text that reads back to the same value ("0.25", "1e+300",
// "-1e-300", "9223372036854775807"), never printf's fixed six decimals, which turn 1e-300 into
// "-0.000000" and 1e300 into a 300-digit number.
#include <cstdint>
#include <string>

namespace glarelab {

std::string number_text(double value);
std::string number_text(std::int64_t value);
std::string number_text(std::uint64_t value);
inline std::string number_text(int value) { return number_text(static_cast<std::int64_t>(value)); }

}  // namespace glarelab
