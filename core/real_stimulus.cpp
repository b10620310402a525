#include "core/real_stimulus.h"

namespace glarelab {

bool is_real_stimulus(std::string_view scene) { return scene.starts_with(kRealStimulusPrefix); }

std::string real_stimulus_object(std::string_view scene) {
  if (!is_real_stimulus(scene)) return "";
  std::string_view object = scene.substr(kRealStimulusPrefix.size());
  constexpr std::string_view kBlanks = " \t\r\n";
  const std::size_t first = object.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return "";
  object = object.substr(first, object.find_last_not_of(kBlanks) - first + 1);
  return std::string(object);
}

std::string real_stimulus_instruction(std::string_view object) {
  return "Look at the real " + std::string(object) + ", then answer.";
}

}  // namespace glarelab
