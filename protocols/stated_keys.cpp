#include "protocols/stated_keys.h"

#include <exception>

#include <toml++/toml.h>

#include "protocols/toml_table_reader.h"

namespace glarelab {

StatedKey stated_key(const std::string& source_file, std::string_view table, std::string_view key) {
  StatedKey stated;
  stated.table = SourceLocation{source_file, 0, 0};
  if (source_file.starts_with("<")) {
    stated.value = stated.table;
    return stated;
  }
  toml::table root;
  try {
    root = toml::parse_file(source_file);
  } catch (const std::exception&) {  // toml::parse_error, or the file is gone
    return stated;
  }
  const toml::table* section = root[table].as_table();
  if (section == nullptr) return stated;
  stated.table = to_location(section->source(), source_file);
  if (const toml::node* value = section->get(key)) stated.value = to_location(value->source(), source_file);
  return stated;
}

}  // namespace glarelab
