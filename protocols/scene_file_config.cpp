#include "protocols/scene_file_config.h"

#include <optional>
#include <string>

namespace glarelab {

void read_scene_file_options(TableReader& reader, SceneSpec& scene) {
  if (const std::optional<std::string> negative = reader.string("negative_pixels")) {
    if (*negative == "refuse") scene.negative_pixels = NegativePixels::refuse;
    else if (*negative == "clamp") scene.negative_pixels = NegativePixels::clamp;
    else
      reader.fail("negative_pixels", "unknown value '" + *negative +
                                         "' (supported: 'refuse', the default, and 'clamp', which sets them to 0)");
  }
  if (const std::optional<std::string> fit = reader.string("fit")) {
    if (*fit == "refuse") scene.fit = SceneFit::refuse;
    else if (*fit == "scale") scene.fit = SceneFit::scale;
    else if (*fit == "crop") scene.fit = SceneFit::crop;
    else
      reader.fail("fit", "unknown value '" + *fit +
                             "' (supported: 'refuse', the default, 'scale' and 'crop', for a scene larger than its place)");
  }
}

toml::table scene_file_toml(const SceneSpec& scene) {
  return toml::table{{"file", scene.file},
                     {"scale_cd_m2", scene.scale_cd_m2},
                     {"negative_pixels", to_string(scene.negative_pixels)},
                     {"fit", to_string(scene.fit)}};
}

}  // namespace glarelab
