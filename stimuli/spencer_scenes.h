#pragma once
// The stimuli of Spencer et al. 1995, section 4, drawn at load time (scenes with a `generator` in
// the experiment file; docs/EXPERIMENT_FILES.md, "Generated scenes"). Each is a square grey image
// in cd/m2 on black (the paper's "screen with a black background"), its features centred, edges
// antialiased by exact pixel-area coverage (stimuli/disc_coverage.h):
// - disc_annulus: the comparison, "a hardware-drawn disc surrounded by an annulus of one-third the
//   intensity of the central disc": the disc at disc_fraction_of_peak of the display's peak, the
//   annulus out to annulus_diameter_deg at a third of that;
// - light_source: the glare image's source on its own ("in the center of a black field"), a disc
//   whose brightest pixel is disc_fraction_of_peak of the peak (Spencer: 75 %); a source smaller
//   than a pixel is a point whose pixel reaches that value;
// - desk_lamp: the same source as the bulb of a desk lamp on a desk ("the context of a light bulb
//   at the end of a desk lamp on a desk"), the bulb at the image centre like the source alone, so
//   the two groups differ only by the context around it.
// The glare is not drawn here: the session's glare stage adds it to the reference side.
#include "core/display_spec.h"
#include "core/image.h"
#include "core/scene_spec.h"

namespace glarelab {

// Luminances (fractions of the display peak) of the desk-lamp context: a dim room lit by the lamp.
// The context must stay well below the source so that the brightest thing is the bulb, as in the
// paper's Figure 11(c).
inline constexpr double kDeskTopFractionOfPeak = 0.04;
inline constexpr double kDeskEdgeFractionOfPeak = 0.08;
inline constexpr double kLampBodyFractionOfPeak = 0.025;
inline constexpr double kLampShadeFractionOfPeak = 0.06;

// Sizes in pixels of a generated scene on `display` (2 d tan(deg / 2) / pitch).
struct GeneratedScenePixels {
  double disc_diameter_px = 0.0;
  double annulus_diameter_px = 0.0;
};
GeneratedScenePixels generated_scene_pixels(const GeneratedSceneSpec& spec, const DisplaySpec& display);

// The scene in cd/m2 (R = G = B = luminance). std::invalid_argument when the spec does not fit its
// image (protocols/ refuses such files with their location first).
ImageRGBA draw_generated_scene(const GeneratedSceneSpec& spec, const DisplaySpec& display);

}  // namespace glarelab
