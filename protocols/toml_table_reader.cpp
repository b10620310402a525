#include "protocols/toml_table_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/number_text.h"

namespace glarelab {

std::string describe_toml_type(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

SourceLocation to_location(const toml::source_region& region, const std::string& file) {
  return SourceLocation{file, static_cast<int>(region.begin.line), static_cast<int>(region.begin.column)};
}

namespace {

// Levenshtein distance, for "did you mean" suggestions (keys are short, so O(n*m) is nothing).
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1);
  std::vector<std::size_t> current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

}  // namespace

TableReader::TableReader(const toml::table& table, std::string path, std::string file)
    : table_(table), path_(std::move(path)), file_(std::move(file)) {}

std::string TableReader::key_path(std::string_view key) const {
  if (key.empty()) return path_;
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

std::string TableReader::table_title() const {
  return path_.empty() ? std::string("the top level") : "[" + path_ + "]";
}

SourceLocation TableReader::table_location() const { return to_location(table_.source(), file_); }

SourceLocation TableReader::key_location(std::string_view key) const {
  const auto found = table_.find(key);
  if (found == table_.end()) return table_location();
  return to_location(found->first.source(), file_);
}

SourceLocation TableReader::value_location(std::string_view key) const {
  const toml::node* value = table_.get(key);
  return value == nullptr ? table_location() : to_location(value->source(), file_);
}

const toml::node* TableReader::node(std::string_view key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
  const toml::node* value = table_.get(key);
  if (value != nullptr) consumed_.emplace(key);
  return value;
}

std::optional<std::string> TableReader::string(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_string()) fail(key, "expected a string, found " + describe_toml_type(*value));
  return value->as_string()->get();
}

std::optional<std::int64_t> TableReader::integer(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_integer()) fail(key, "expected an integer, found " + describe_toml_type(*value));
  return value->as_integer()->get();
}

std::optional<double> TableReader::number(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return std::nullopt;
  double result = 0.0;
  if (value->is_integer()) {
    result = static_cast<double>(value->as_integer()->get());
  } else if (value->is_floating_point()) {
    result = value->as_floating_point()->get();
  } else {
    fail(key, "expected a number, found " + describe_toml_type(*value));
  }
  // TOML allows inf and nan; no physical quantity in an experiment file can take them.
  if (!std::isfinite(result)) fail(key, "expected a finite number");
  return result;
}

std::optional<bool> TableReader::boolean(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_boolean()) fail(key, "expected a boolean, found " + describe_toml_type(*value));
  return value->as_boolean()->get();
}

const toml::table* TableReader::table(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return nullptr;
  if (!value->is_table()) fail(key, "expected a table, found " + describe_toml_type(*value));
  return value->as_table();
}

const toml::array* TableReader::array(std::string_view key) {
  const toml::node* value = node(key);
  if (value == nullptr) return nullptr;
  if (!value->is_array()) fail(key, "expected an array, found " + describe_toml_type(*value));
  return value->as_array();
}

void TableReader::consume_all() {
  for (const auto& entry : table_) consumed_.emplace(entry.first.str());
}

void TableReader::fail(std::string_view key, const std::string& message) const {
  throw ConfigError(value_location(key), key_path(key), message);
}

void TableReader::fail_at_key(std::string_view key, const std::string& message) const {
  throw ConfigError(key_location(key), key_path(key), message);
}

void TableReader::report_unused() const {
  // toml::table iterates in key order; report the unused key that comes first in the file.
  const toml::key* first = nullptr;
  for (const auto& entry : table_) {
    if (consumed_.count(entry.first.str()) != 0) continue;
    const toml::source_position position = entry.first.source().begin;
    if (first == nullptr || position < first->source().begin) first = &entry.first;
  }
  if (first == nullptr) return;

  const std::string_view unknown = first->str();
  std::string suggestion;
  std::size_t best = std::numeric_limits<std::size_t>::max();
  for (const std::string& candidate : known_) {
    const std::size_t distance = edit_distance(unknown, candidate);
    // Close enough to be a typo: a couple of edits, or a third of the word for long keys.
    if (distance < best && (distance <= 2 || distance * 3 <= candidate.size())) {
      best = distance;
      suggestion = candidate;
    }
  }
  std::string allowed;
  for (const std::string& candidate : known_) allowed += (allowed.empty() ? "" : ", ") + candidate;

  std::string message = "unknown key '" + std::string(unknown) + "' in " + table_title() + " (";
  if (!suggestion.empty()) message += "did you mean '" + suggestion + "'?; ";
  message += "allowed: " + allowed + ")";
  throw ConfigError(to_location(first->source(), file_), key_path(unknown), message);
}

const std::string& expect_string(const toml::node& node, const std::string& key_path, const std::string& file) {
  if (!node.is_string()) {
    throw ConfigError(to_location(node.source(), file), key_path,
                      "expected a string, found " + describe_toml_type(node));
  }
  return node.as_string()->get();
}

double TableReader::number_in_range(std::string_view key, double fallback, double minimum, double maximum,
                                    std::string_view unit) {
  const std::optional<double> value = number(key);
  if (!value) return fallback;
  if (!(*value >= minimum && *value <= maximum)) {
    fail(key, "must be from " + number_text(minimum) + " to " + number_text(maximum) +
                  (unit.empty() ? "" : " " + std::string(unit)) + ", found " + number_text(*value));
  }
  return *value;
}

std::int64_t TableReader::integer_in_range(std::string_view key, std::int64_t fallback, std::int64_t minimum,
                                           std::int64_t maximum) {
  const std::optional<std::int64_t> value = integer(key);
  if (!value) return fallback;
  if (*value < minimum || *value > maximum) {
    fail(key, "must be from " + number_text(minimum) + " to " + number_text(maximum) + ", found " + number_text(*value));
  }
  return *value;
}

double TableReader::positive_number(std::string_view key, double fallback) {
  const std::optional<double> value = number(key);
  if (!value) return fallback;
  if (!(*value > 0.0)) fail(key, "must be > 0, found " + number_text(*value));
  return *value;
}

double TableReader::non_negative_number(std::string_view key, double fallback) {
  const std::optional<double> value = number(key);
  if (!value) return fallback;
  if (!(*value >= 0.0)) fail(key, "must be >= 0, found " + number_text(*value));
  return *value;
}

std::optional<std::vector<ArrayString>> TableReader::distinct_names(
    std::string_view key, const std::string& what, const std::function<void(const ArrayString&)>& check) {
  const toml::array* names = array(key);
  if (names == nullptr) return std::nullopt;
  std::vector<ArrayString> result;
  for (std::size_t i = 0; i < names->size(); ++i) {
    const toml::node& element = *names->get(i);
    ArrayString name;
    name.key = key_path(key) + "[" + std::to_string(i) + "]";
    name.value = expect_string(element, name.key, file_);
    name.where = to_location(element.source(), file_);
    if (name.value.empty()) throw ConfigError(name.where, name.key, what + " names must not be empty");
    if (check) check(name);
    for (const ArrayString& earlier : result)
      if (earlier.value == name.value) throw ConfigError(name.where, name.key, "duplicate " + what + " '" + name.value + "'");
    result.push_back(std::move(name));
  }
  return result;
}

}  // namespace glarelab
