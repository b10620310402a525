#include "core/text_limits.h"

#include <cstdint>
#include <vector>

namespace glarelab {
namespace {

void append_hex(std::string& out, const char* prefix, std::uint32_t value, int digits) {
  static const char* const kHex = "0123456789abcdef";
  out += prefix;
  for (int d = digits - 1; d >= 0; --d) out += kHex[(value >> (4 * d)) & 0xFu];
}

bool bare_key_character(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

// The lexical states of TOML 1.0 that matter for nesting: brackets and dots count only outside
// strings and comments.
enum class TomlState { plain, basic_string, literal_string, multiline_basic, multiline_literal, comment };

}  // namespace

std::size_t utf8_length(std::string_view text, std::size_t i, std::uint32_t& code_point) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length = 0;
  if (lead < 0x80) {
    code_point = lead;
    return 1;
  }
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
    code_point = lead & 0x1Fu;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    code_point = lead & 0x0Fu;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    code_point = lead & 0x07u;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(i + k) & 0x3Fu);
  }
  if (length == 3 && (code_point < 0x800 || (code_point >= 0xD800 && code_point <= 0xDFFF))) return 0;
  if (length == 4 && (code_point < 0x10000 || code_point > 0x10FFFF)) return 0;
  return length;
}

std::optional<TextLimitFault> toml_limit_fault(std::string_view text) {
  if (text.size() > kMaxTomlBytes) {
    return TextLimitFault{1, 1, "the TOML text is " + std::to_string(text.size()) + " bytes; glarelab reads at most " +
                                    std::to_string(kMaxTomlBytes) + " (64 MiB)"};
  }
  // Depth = for each open bracket, 1 plus the dotted parts of the key before it (a.b.c = { ... }
  // opens three tables and the inline one), plus the dots of the key being read now.
  std::vector<int> open_depths;
  int open_total = 0;
  int dots = 0;
  std::size_t line = 1, column = 0;
  TomlState state = TomlState::plain;
  const auto starts = [&](std::size_t i, std::string_view token) { return text.substr(i, token.size()) == token; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      column = 0;
    } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
      ++column;
    }
    switch (state) {
      case TomlState::comment:
        if (c == '\n') state = TomlState::plain;
        continue;
      case TomlState::basic_string:
        if (c == '\\' && i + 1 < text.size() && text[i + 1] != '\n') ++i;  // \" does not end it
        else if (c == '"' || c == '\n') state = TomlState::plain;
        continue;
      case TomlState::literal_string:
        if (c == '\'' || c == '\n') state = TomlState::plain;
        continue;
      case TomlState::multiline_basic:
        if (c == '\\' && i + 1 < text.size() && text[i + 1] != '\n') ++i;
        else if (starts(i, "\"\"\"")) state = TomlState::plain, i += 2, column += 2;
        continue;
      case TomlState::multiline_literal:
        if (starts(i, "'''")) state = TomlState::plain, i += 2, column += 2;
        continue;
      case TomlState::plain:
        break;
    }
    if (c == '#') {
      state = TomlState::comment;
      dots = 0;
    } else if (starts(i, "\"\"\"")) {
      state = TomlState::multiline_basic, i += 2, column += 2;
    } else if (starts(i, "'''")) {
      state = TomlState::multiline_literal, i += 2, column += 2;
    } else if (c == '"') {
      state = TomlState::basic_string;  // a quoted part of a dotted key keeps the count
    } else if (c == '\'') {
      state = TomlState::literal_string;
    } else if (c == '.') {
      ++dots;
    } else if (c == '[' || c == '{') {
      open_depths.push_back(1 + dots);
      open_total += 1 + dots;
      dots = 0;
    } else if (c == ']' || c == '}') {
      if (!open_depths.empty()) {
        open_total -= open_depths.back();
        open_depths.pop_back();
      }
      dots = 0;
    } else if (!bare_key_character(c) && c != ' ' && c != '\t') {
      dots = 0;  // '=', ',', a line break: the key (or number) ended
    }
    if (open_total + dots > kMaxTomlNesting) {
      return TextLimitFault{line, column,
                            "nested deeper than " + std::to_string(kMaxTomlNesting) +
                                " levels (tables, parts of dotted keys, arrays and inline tables together); glarelab "
                                "reads at most " + std::to_string(kMaxTomlNesting)};
    }
  }
  return std::nullopt;
}

std::string escaped_for_terminal(std::string_view text, bool keep_line_breaks) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    std::uint32_t code_point = 0;
    const std::size_t length = utf8_length(text, i, code_point);
    if (length == 0) {
      append_hex(out, "\\x", static_cast<unsigned char>(text[i]), 2);  // not UTF-8
      ++i;
      continue;
    }
    if (code_point < 0x20 || code_point == 0x7F) {
      if (keep_line_breaks && (code_point == '\n' || code_point == '\t')) out += static_cast<char>(code_point);
      else if (code_point == '\n') out += "\\n";
      else if (code_point == '\t') out += "\\t";
      else if (code_point == '\r') out += "\\r";
      else append_hex(out, "\\x", code_point, 2);
    } else if (code_point >= 0x80 && code_point <= 0x9F) {
      append_hex(out, "\\u", code_point, 4);  // C1 controls: U+009B is a one-byte CSI on some terminals
    } else {
      out.append(text.substr(i, length));
    }
    i += length;
  }
  return out;
}

std::string shortened_value(std::string_view text, std::size_t max_bytes, bool keep_line_breaks) {
  if (text.size() <= max_bytes) return escaped_for_terminal(text, keep_line_breaks);
  std::size_t cut = max_bytes;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // not inside a character
  return escaped_for_terminal(text.substr(0, cut), keep_line_breaks) + "... (" + std::to_string(text.size()) + " bytes in all)";
}

std::string shell_quoted(std::string_view word) {
  const auto plain = [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
           std::string_view("%+,-./:=@_").find(c) != std::string_view::npos;
  };
  bool all_plain = !word.empty();
  for (const char c : word) all_plain = all_plain && plain(c);
  if (all_plain) return std::string(word);
  std::string out = "'";
  for (const char c : word) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

}  // namespace glarelab
