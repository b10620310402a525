#include "protocols/json_text.h"

#include <cstdint>

#include "core/text_limits.h"

namespace glarelab {

std::string json_quote(std::string_view text) {
  static const char* const kHex = "0123456789abcdef";
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    const auto code = static_cast<unsigned char>(c);
    switch (c) {
      case '"': out += "\\\""; ++i; continue;
      case '\\': out += "\\\\"; ++i; continue;
      case '\b': out += "\\b"; ++i; continue;
      case '\f': out += "\\f"; ++i; continue;
      case '\n': out += "\\n"; ++i; continue;
      case '\r': out += "\\r"; ++i; continue;
      case '\t': out += "\\t"; ++i; continue;
      default: break;
    }
    if (code < 0x20) {  // other control characters must be \u escapes (RFC 8259 section 7)
      out += "\\u00";
      out += kHex[code >> 4];
      out += kHex[code & 0x0F];
      ++i;
      continue;
    }
    std::uint32_t code_point = 0;
    const std::size_t length = utf8_length(text, i, code_point);
    if (length == 0) {
      out += "\\ufffd";
      ++i;
      continue;
    }
    out.append(text.substr(i, length));
    i += length;
  }
  out += '"';
  return out;
}

JsonObjectWriter& JsonObjectWriter::add(std::string_view key, std::string_view value) {
  if (!body_.empty()) body_ += ',';
  body_ += json_quote(key);
  body_ += ':';
  body_ += json_quote(value);
  return *this;
}

}  // namespace glarelab
