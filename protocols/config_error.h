#pragma once
// Errors in experiment files and condition tables. what() reads "FILE:LINE:COLUMN: key 'KEY': MESSAGE"
// (the key part only when a key is involved), the form compilers use, so editors can jump to it.
#include <stdexcept>
#include <string>

namespace glarelab {

struct SourceLocation {
  std::string file;
  int line = 0;    // 1-based; 0 when unknown
  int column = 0;  // 1-based; 0 when unknown
  std::string to_string() const;  // "file:line:column" (omits zeros)
};

class ConfigError : public std::runtime_error {
 public:
  ConfigError(SourceLocation where, std::string key, const std::string& message);
  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string key_;
  std::string message_;
};

}  // namespace glarelab
