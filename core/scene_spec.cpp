#include "core/scene_spec.h"

namespace glarelab {

std::string to_string(SceneGenerator generator) {
  switch (generator) {
    case SceneGenerator::disc_annulus: return "disc_annulus";
    case SceneGenerator::light_source: return "light_source";
    case SceneGenerator::desk_lamp: return "desk_lamp";
  }
  return "disc_annulus";
}

}  // namespace glarelab
