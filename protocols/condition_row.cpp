#include "protocols/experiment.h"

namespace glarelab {

const std::string* ConditionRow::find(const std::string& column) const {
  for (const auto& [key, value] : fields) {
    if (key == column) return &value;
  }
  return nullptr;
}

std::string ConditionRow::name() const {
  // An empty "name" cell is as good as none: fall back to the row's position.
  const std::string* named = find("name");
  if (named != nullptr && !named->empty()) return *named;
  return "row " + std::to_string(number);
}

}  // namespace glarelab
