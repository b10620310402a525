#pragma once
// One HDR scene a session may show: its name, its OpenEXR file (or the generator that draws it)
// and the scale that turns its pixel values into luminance. Read from the experiment file by
// protocols/, loaded by stimuli/scene_library.h; in the base layer because both need it and neither
// may include the other.
#include <optional>
#include <string>

#include "core/errors.h"

namespace glarelab {

// A scene drawn at load time instead of read from a file: the stimuli of Spencer et al. 1995,
// section 4 (stimuli/spencer_scenes.h). Sizes are degrees of visual angle, turned into pixels with
// the display's viewing distance and pixel pitch; luminances are fractions of the display's peak.
enum class SceneGenerator {
  disc_annulus,  // the comparison: a disc inside an annulus of one third its luminance, on black
  light_source,  // the glare image's source alone on black (Spencer's "without context")
  desk_lamp,     // the same source as the bulb of a desk lamp on a desk ("with context")
};

struct GeneratedSceneSpec {
  SceneGenerator generator = SceneGenerator::disc_annulus;
  int size_px = 300;                   // the square image's side (Spencer: 300 x 300 px windows)
  double disc_diameter_deg = 0.5;      // the disc, or the source
  double annulus_diameter_deg = 1.5;   // outer diameter of the annulus (disc_annulus only)
  double disc_fraction_of_peak = 1.0;  // luminance of the disc (or the source's brightest pixel) / display peak
};

// What loading does with a photograph's negative pixels (camera noise, colour-space conversion
// outside the gamut, filter ringing): a luminance cannot be negative, so either the scene is
// refused or they are set to 0 and the count and the fraction of the energy removed reported
// (stimuli/scene_library.h).
enum class NegativePixels { refuse, clamp };

// What a scene that does not fit its place on the display (stimuli/layout.h) becomes: refused,
// scaled down as a whole (area-averaged) or cropped about its centre.
enum class SceneFit { refuse, scale, crop };

struct SceneSpec {
  std::string name;
  std::string file;            // absolute path of the OpenEXR image; empty for a generated scene
  double scale_cd_m2 = 1.0;    // multiplies pixel values to give luminance in cd/m2
  std::optional<GeneratedSceneSpec> generated;
  NegativePixels negative_pixels = NegativePixels::refuse;
  SceneFit fit = SceneFit::refuse;
  SourceLocation where;
};

std::string to_string(SceneGenerator generator);
std::string to_string(NegativePixels negative_pixels);
std::string to_string(SceneFit fit);

}  // namespace glarelab
