#include "runner/cli/option_checks.h"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <vector>

#include "core/number_text.h"
#include "glare/eye_parameters.h"

namespace glarelab::cli {
namespace {

std::string text(double value) { return number_text(value); }

// The option's text as CLI11 will convert it, or an explanation why it is not a number.
bool parse(const std::string& input, double& value, std::string& error) {
  if (!CLI::detail::lexical_cast(input, value)) {
    error = "must be a number, found '" + input + "'";
    return false;
  }
  if (!std::isfinite(value)) {
    error = "must be a finite number, found " + input;
    return false;
  }
  return true;
}

std::string with_unit(double value, const std::string& unit) { return text(value) + (unit.empty() ? "" : " " + unit); }

}  // namespace

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& input) {
        double value = 0.0;
        std::string error;
        return parse(input, value, error) ? std::string() : error;
      },
      "FINITE");
}

CLI::Validator finite_number_in(double low, double high, const std::string& unit) {
  return CLI::Validator(
      [low, high, unit](std::string& input) {
        double value = 0.0;
        std::string error;
        if (!parse(input, value, error)) return error;
        if (value < low || value > high)
          return "must be from " + text(low) + " to " + with_unit(high, unit) + ", found " + input;
        return std::string();
      },
      "FINITE in [" + text(low) + " - " + text(high) + "]");
}

CLI::Validator finite_positive_number(const std::string& unit) {
  return CLI::Validator(
      [unit](std::string& input) {
        double value = 0.0;
        std::string error;
        if (!parse(input, value, error)) return error;
        if (!(value > 0.0)) return "must be > 0" + std::string(unit.empty() ? "" : " " + unit) + ", found " + input;
        return std::string();
      },
      "POSITIVE");
}

CLI::Validator eye_model_time_s() {
  return CLI::Validator(
      [](std::string& input) {
        double value = 0.0;
        std::string error;
        if (!parse(input, value, error)) return error;
        if (value < 0.0) return "must be >= 0 s, found " + input;
        if (value > kMaxEyeModelTime_s)
          return std::string("must be at most ") + kMaxEyeModelTimeText + ", found " + input +
                 " s (a session is hours long at most; is this a time in ms or ns?)";
        return std::string();
      },
      "SECONDS in [0 - " + text(kMaxEyeModelTime_s) + "]");
}

CLI::Validator file_extension_in(std::initializer_list<const char*> extensions, const std::string& what) {
  const std::vector<std::string> allowed(extensions.begin(), extensions.end());
  std::string listed;
  for (const std::string& extension : allowed) listed += (listed.empty() ? "" : " or ") + extension;
  return CLI::Validator(
      [allowed, listed, what](std::string& input) {
        std::string extension = std::filesystem::path(input).extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (std::find(allowed.begin(), allowed.end(), extension) != allowed.end()) return std::string();
        return "'" + input + "': " + what + " must end in " + listed +
               (extension.empty() ? std::string(" (it has no extension)") : ", not " + extension);
      },
      "FILE(" + listed + ")");
}

CLI::Validator whole_number_check(std::int64_t minimum, std::int64_t maximum) {
  const std::string bounds = "a whole number from " + number_text(minimum) + " to " + number_text(maximum);
  return CLI::Validator(
      [=](std::string& input) -> std::string {
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(input.data(), input.data() + input.size(), value);
        const bool digits_only = !input.empty() && input.find_first_not_of("0123456789") == std::string::npos;
        if (!digits_only || error != std::errc() || end != input.data() + input.size() || value < minimum ||
            value > maximum)
          return "must be " + bounds + ", found '" + input + "'";
        return {};
      },
      bounds);
}

CLI::Validator seed_check() { return whole_number_check(0, kMaxSeed); }

}  // namespace glarelab::cli
