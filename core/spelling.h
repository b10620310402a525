#pragma once
// The words of a choice: one table per enumeration pairs each value with the text an experiment
// file or a command-line flag writes for it, so that reading (text to value) and writing (value
// to text, in the log and the resolved experiment) go through the same table and cannot drift.
//
// An enumeration takes part by declaring, in its own namespace, a function found by argument-
// dependent lookup that returns its table, e.g.
//   enum class PupilSource { tracker, model };
//   inline constexpr Spelling<PupilSource> kPupilSourceSpellings[] = {{PupilSource::tracker, "tracker"},
//                                                                     {PupilSource::model, "model"}};
//   constexpr std::span<const Spelling<PupilSource>> spellings(PupilSource) { return kPupilSourceSpellings; }
// The table's order is the order the accepted values are listed in messages.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace glarelab {

template <typename Enum>
struct Spelling {
  Enum value;
  std::string_view text;
};

// The text of `value` (empty only for a value missing from its table, which the tables do not allow).
template <typename Enum>
constexpr std::string_view spelling(Enum value) {
  for (const Spelling<Enum>& entry : spellings(Enum{}))
    if (entry.value == value) return entry.text;
  return {};
}

// The value spelt `text`, or nothing for a text that is not in the table (case matters).
template <typename Enum>
constexpr std::optional<Enum> parse_spelling(std::string_view text) {
  for (const Spelling<Enum>& entry : spellings(Enum{}))
    if (entry.text == text) return entry.value;
  return std::nullopt;
}

// The accepted texts for messages, in table order: "'auto', 'cpu', 'gl'".
template <typename Enum>
std::string spelling_list() {
  std::string listed;
  for (const Spelling<Enum>& entry : spellings(Enum{}))
    listed += (listed.empty() ? "'" : ", '") + std::string(entry.text) + "'";
  return listed;
}

}  // namespace glarelab
