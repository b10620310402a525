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

std::string to_string(NegativePixels negative_pixels) {
  return negative_pixels == NegativePixels::clamp ? "clamp" : "refuse";
}

std::string to_string(SceneFit fit) {
  switch (fit) {
    case SceneFit::refuse: return "refuse";
    case SceneFit::scale: return "scale";
    case SceneFit::crop: return "crop";
  }
  return "refuse";
}

}  // namespace glarelab
