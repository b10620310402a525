#pragma once
// Bounds on text that other people write, checked before a parser or the terminal sees it.
//  - Nesting: toml++ 3.3 builds one table per part of a dotted key and walks the tree recursively
//    (its region pass, its destructors), so a key of a few hundred thousand parts overflows the
//    stack; nlohmann::json's dump() recurses per level too. Both readers see text only after the
//    nesting check below passed.
//  - Messages: text from experiment files, condition tables and databases is quoted in errors;
//    its control characters are escaped (an ESC sequence in a cell must not retitle or clear the
//    terminal) and a long value is cut with its length (a 20 MB cell is not echoed whole).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace glarelab {

// The largest TOML text read (an experiment file or a stored configuration): 64 MiB, far beyond
// any experiment (inline condition rows of a large design are a few MB; large tables are CSV).
inline constexpr std::size_t kMaxTomlBytes = std::size_t{64} << 20;
// The deepest TOML nesting read: tables, parts of dotted keys, arrays and inline tables together.
// An experiment file needs 4 ([observer.refraction] inside a dotted key of an inline table).
inline constexpr int kMaxTomlNesting = 128;
// The deepest JSON nesting read (a trial's condition is a flat object: depth 1).
inline constexpr int kMaxJsonNesting = 64;

// Where in a text a limit is passed (1-based; the column counts characters, not bytes).
struct TextLimitFault {
  std::size_t line = 1;
  std::size_t column = 1;
  std::string message;
};

// The first place where `toml_text` passes kMaxTomlBytes or kMaxTomlNesting; nullopt when it
// stays within both. Strings and comments are skipped as TOML 1.0 spells them; text that is not
// TOML is left for the parser to refuse.
std::optional<TextLimitFault> toml_limit_fault(std::string_view toml_text);

// Text for a message: control characters (C0, DEL, C1) and bytes that are not UTF-8 become
// visible escapes (\n, \t, \x1b, \u009b); newlines and tabs stay as they are when
// `keep_line_breaks` (a message of several lines). Printable UTF-8 passes unchanged.
std::string escaped_for_terminal(std::string_view text, bool keep_line_breaks = false);

// A value for a message: escaped as above and, when longer than `max_bytes`, cut at a character
// boundary with its full length said ("abc... (20971520 bytes in all)").
// `keep_line_breaks` as for escaped_for_terminal.
std::string shortened_value(std::string_view text, std::size_t max_bytes = 200, bool keep_line_breaks = false);

// `word` as one word of a POSIX shell command line: as it is when it holds only characters no shell
// treats specially (letters, digits, and % + , - . / : = @ _), else in single quotes, a single quote
// written '\''. A printed command pasted into bash then runs exactly what was printed: a path holding
// $(...) is not executed, parentheses in a name are not syntax.
std::string shell_quoted(std::string_view word);

// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not one (overlong
// forms, surrogates and code points above U+10FFFF are invalid, RFC 3629 section 4); the code
// point goes to `code_point`. The one check behind the terminal's escaping and JSON's quoting.
std::size_t utf8_length(std::string_view text, std::size_t i, std::uint32_t& code_point);

}  // namespace glarelab
