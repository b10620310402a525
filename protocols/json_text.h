#pragma once
// Flat JSON objects with string values, for the condition record stored with each trial
// (RFC 8259). Writing is all that is needed, so no JSON library is pulled in.
#include <string>
#include <string_view>

namespace glarelab {

// The JSON string literal for `text`, quotes included. Quote, backslash and control characters
// are escaped; valid UTF-8 passes through; bytes that are not valid UTF-8 become U+FFFD, so the
// result is always valid JSON.
std::string json_quote(std::string_view text);

class JsonObjectWriter {
 public:
  // Keys are written in the order added; callers keep them unique (RFC 8259 leaves duplicate
  // names undefined).
  JsonObjectWriter& add(std::string_view key, std::string_view value);
  std::string str() const { return "{" + body_ + "}"; }

 private:
  std::string body_;
};

}  // namespace glarelab
