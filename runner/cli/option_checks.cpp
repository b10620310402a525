#include "runner/cli/option_checks.h"

#include <charconv>
#include <cmath>

#include "core/number_text.h"

namespace glarelab::cli {

CLI::Validator whole_number_check(std::int64_t minimum, std::int64_t maximum) {
  const std::string bounds = "a whole number from " + number_text(minimum) + " to " + number_text(maximum);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        const bool digits_only = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        if (!digits_only || error != std::errc() || end != text.data() + text.size() || value < minimum ||
            value > maximum)
          return "must be " + bounds + ", found '" + text + "'";
        return {};
      },
      bounds);
}

CLI::Validator seed_check() {
  CLI::Validator check = whole_number_check(0, kMaxSeed);
  check.description("a whole number from 0 to 2^63 - 1");
  return check;
}

CLI::Validator finite_number_check(double minimum, double maximum, const std::string& unit) {
  const std::string bounds = "a number from " + number_text(minimum) + " to " + number_text(maximum) +
                             (unit.empty() ? "" : " " + unit);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0.0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(value) ||
            value < minimum || value > maximum)
          return "must be " + bounds + ", found '" + text + "'";
        return {};
      },
      bounds);
}

}  // namespace glarelab::cli
