#pragma once
// One HDR scene a session may show: its name, its OpenEXR file and the scale that turns its pixel
// values into luminance. Read from the experiment file by protocols/, loaded by
// stimuli/scene_library.h; in the base layer because both need it and neither may include the other.
#include <string>

#include "core/errors.h"

namespace glarelab {

struct SceneSpec {
  std::string name;
  std::string file;            // absolute path of the OpenEXR image
  double scale_cd_m2 = 1.0;    // multiplies pixel values to give luminance in cd/m2
  SourceLocation where;
};

}  // namespace glarelab
