#pragma once
// Strict reading of one TOML table: every key a reader asks for (present or not) becomes "known",
// and report_unused() turns any key present in the file but never asked for into a ConfigError
// with a spelling suggestion. The idea is pbrt-v4's ParameterDictionary::ReportUnused: a typo in
// an experiment file must stop the run instead of silently falling back to a default.
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "core/errors.h"

namespace glarelab {

// "a string", "an integer", ... for error messages.
std::string describe_toml_type(const toml::node& node);
SourceLocation to_location(const toml::source_region& region, const std::string& file);

// One element of a string array: its value, dotted key ("procedure.responses[1]") and location.
struct ArrayString {
  std::string value;
  std::string key;
  SourceLocation where;
};

// 10,000 repetitions of even one condition is 10,000 trials, many hours of a participant's time;
// more is a typo, and would only fill memory with a trial list nobody can run.
inline constexpr std::int64_t kMaxRepetitions = 10000;

class TableReader {
 public:
  // `path` is the dotted name of the table ("" for the document root, "observer.simulated");
  // `file` names the document in error locations.
  TableReader(const toml::table& table, std::string path, std::string file);

  const std::string& file() const { return file_; }
  // "procedure.stimulus_frames" for key "stimulus_frames" of [procedure].
  std::string key_path(std::string_view key) const;
  SourceLocation table_location() const;
  // Where the key itself is written; the table's location when the key is absent.
  SourceLocation key_location(std::string_view key) const;
  // Where the key's value starts; the table's location when the key is absent.
  SourceLocation value_location(std::string_view key) const;

  // Each accessor marks the key known and consumed, returns nothing when the key is absent and
  // throws ConfigError ("expected an integer, found a string") when its type is wrong.
  const toml::node* node(std::string_view key);
  std::optional<std::string> string(std::string_view key);
  std::optional<std::int64_t> integer(std::string_view key);
  // A float or an integer (TOML writes 60 and 60.0 differently; both mean sixty); must be finite.
  std::optional<double> number(std::string_view key);
  std::optional<bool> boolean(std::string_view key);
  const toml::table* table(std::string_view key);
  const toml::array* array(std::string_view key);

  // Marks every present key consumed: for tables whose keys are names chosen by the user.
  void consume_all();

  // ConfigError about the key's value, at the value (or at the table when the key is absent).
  [[noreturn]] void fail(std::string_view key, const std::string& message) const;
  // ConfigError about the key itself, at the key.
  [[noreturn]] void fail_at_key(std::string_view key, const std::string& message) const;
  // Throws for the first key, in document order, that no accessor asked for.
  void report_unused() const;
  // A number in [minimum, maximum] (`unit` is printed after the bounds, e.g. "Hz"): the value, or
  // `fallback` when the key is absent. The bounds say what a real setup can be; beyond them a value
  // is a typo, not an experiment ("must be from 1 to 1000 Hz, found 1e+300").
  double number_in_range(std::string_view key, double fallback, double minimum, double maximum,
                         std::string_view unit = {});
  // An integer in [minimum, maximum]: the value, or `fallback` when the key is absent.
  std::int64_t integer_in_range(std::string_view key, std::int64_t fallback, std::int64_t minimum,
                                std::int64_t maximum);
  // How often a design unit (condition row, block) repeats: 1 to kMaxRepetitions.
  int repetitions(std::string_view key, int fallback) {
    return static_cast<int>(integer_in_range(key, fallback, 1, kMaxRepetitions));
  }
  // A number that must be > 0: the value, or `fallback` when the key is absent.
  double positive_number(std::string_view key, double fallback);
  // A number that must be >= 0: the value, or `fallback` when the key is absent.
  double non_negative_number(std::string_view key, double fallback);
  // The elements of an array of names, nothing when the key is absent. Each must be a string, not
  // empty ("<what> names must not be empty"), pass `check` (called with each element in order,
  // throwing ConfigError at it), and not repeat an earlier one ("duplicate <what> 'NAME'").
  std::optional<std::vector<ArrayString>> distinct_names(
      std::string_view key, const std::string& what, const std::function<void(const ArrayString&)>& check = {});

 private:
  std::string table_title() const;

  const toml::table& table_;
  std::string path_;
  std::string file_;
  std::vector<std::string> known_;  // in the order first asked for: the "allowed" list
  std::set<std::string, std::less<>> consumed_;
};

// Checks a node found outside a TableReader (an array element) for its type.
const std::string& expect_string(const toml::node& node, const std::string& key_path, const std::string& file);

}  // namespace glarelab
