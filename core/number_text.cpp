#include "core/number_text.h"

#include <charconv>
#include <cmath>

namespace glarelab {

std::string number_text(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  // Without a format, to_chars gives the shortest text that reads back to the same value (C++17
  // [charconv]): what the user wrote, for numbers a person writes (0.25, 1e+300, 123456789).
  const auto shortest = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::size_t digits = 0;
  for (const char* c = buffer; c != shortest.ptr && *c != 'e'; ++c) digits += (*c >= '0' && *c <= '9') ? 1 : 0;
  if (digits <= 9) return std::string(buffer, shortest.ptr);
  // A computed value (1000 / 60 = 16.666666666666668): six significant digits read better.
  const auto rounded = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 6);
  return std::string(buffer, rounded.ptr);
}

std::string number_text(std::int64_t value) { return std::to_string(value); }
std::string number_text(std::uint64_t value) { return std::to_string(value); }

}  // namespace glarelab
