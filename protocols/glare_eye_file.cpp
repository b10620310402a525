#include "protocols/glare_eye_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "core/errors.h"
#include "core/text_limits.h"
#include "protocols/eye_parameters_config.h"
#include "protocols/toml_table_reader.h"

namespace glarelab {

void read_glare_eye_file(const std::string& path, EyeParameters& parameters) {
  namespace fs = std::filesystem;
  const SourceLocation file{path, 0, 0};
  std::error_code error;
  if (!fs::is_regular_file(path, error)) throw ConfigError(file, "", "file not found");
  if (const auto bytes = fs::file_size(path, error); !error && bytes > kMaxTomlBytes)
    throw ConfigError(file, "", "the file is " + std::to_string(bytes) + " bytes; experiment files are at most 64 MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw ConfigError(file, "", "cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string toml_text = text.str();
  // Size and nesting before toml++ (which recurses per level), as the experiment loader does.
  if (const std::optional<TextLimitFault> fault = toml_limit_fault(toml_text))
    throw ConfigError(SourceLocation{path, static_cast<int>(fault->line), static_cast<int>(fault->column)}, "",
                      fault->message);
  toml::table root;
  try {
    root = toml::parse(std::string_view(toml_text), std::string_view(path));
  } catch (const toml::parse_error& parse_error) {
    throw ConfigError(to_location(parse_error.source(), path), "",
                      "TOML syntax error: " + std::string(parse_error.description()));
  }
  TableReader top(root, "", path);
  const toml::table* glare = top.table("glare");
  if (glare == nullptr || !glare->contains("eye"))
    throw ConfigError(file, "glare.eye", "the file has no [glare.eye] table to take the eye from");
  TableReader glare_reader(*glare, "glare", path);
  read_glare_eye(glare_reader, parameters);
}

}  // namespace glarelab
