#include "runner/cli/option_checks.h"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "core/number_text.h"
#include "glare/eye/eye_parameters.h"

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

SpheroCylinder minus_cylinder_form(const SpheroCylinder& prescription) {
  if (!(prescription.cylinder_dioptres > 0.0)) return prescription;
  SpheroCylinder transposed;
  transposed.sphere_dioptres = prescription.sphere_dioptres + prescription.cylinder_dioptres;
  transposed.cylinder_dioptres = -prescription.cylinder_dioptres;
  transposed.axis_deg = std::fmod(prescription.axis_deg + 90.0, 180.0);
  return transposed;
}

SpheroCylinder parse_sphero_cylinder(const std::string& input) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = input.find(',', start);
    fields.push_back(input.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (fields.size() != 3)
    throw std::invalid_argument("must be SPHERE,CYLINDER,AXIS (dioptres, dioptres, TABO degrees), found '" + input + "'");
  const char* names[3] = {"sphere", "cylinder", "axis"};
  const double bounds[3][2] = {{-kMaxSphereDioptres, kMaxSphereDioptres},
                               {-kMaxCylinderDioptres, kMaxCylinderDioptres},
                               {0.0, kMaxAxisDeg}};
  double values[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) {
    std::string error;
    if (!parse(fields[k], values[k], error)) throw std::invalid_argument(std::string("its ") + names[k] + " " + error);
    if (values[k] < bounds[k][0] || values[k] > bounds[k][1])
      throw std::invalid_argument(std::string("its ") + names[k] + " must be from " + text(bounds[k][0]) + " to " +
                                  text(bounds[k][1]) + ", found " + fields[k]);
  }
  return {values[0], values[1], values[2]};
}

CLI::Validator sphero_cylinder_check() {
  return CLI::Validator(
      [](std::string& input) {
        try {
          parse_sphero_cylinder(input);
          return std::string();
        } catch (const std::invalid_argument& error) {
          return std::string(error.what());
        }
      },
      "S,C,A");
}

}  // namespace glarelab::cli
