#pragma once
// Numbers in a report's text (HTML tables, figure labels, terminal lines): a fixed count of
// decimals, or four significant digits, written with the C locale's point whatever the user's.
#include <cstdio>
#include <string>

namespace glarelab::analysis {

inline std::string fixed(double value, int digits = 3) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

inline std::string general(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

}  // namespace glarelab::analysis
