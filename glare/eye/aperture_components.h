#pragma once
// Choosing parts of the eye for a PSF (`glarelab psf --components`): the names, and a filter that
// keeps the primitives of the chosen components (glare/eye/aperture_geometry.h's ApertureComponent tags).
// "pupil" is the stop every PSF has; "lashes" keeps the eyelids' lids and lashes together (one
// procedural mask, glare/eye/eyelids.h); "retina" keeps the retinal particles.
#include <set>
#include <string>

#include "glare/eye/aperture_geometry.h"

namespace glarelab {

const char* aperture_component_name(ApertureComponent component);

struct ComponentSelection {
  std::set<ApertureComponent> kept;  // never holds unspecified: untagged primitives are always kept
};

// Comma-separated names from pupil, lens, gratings, vitreous, cornea, retina, lashes, or "all".
// Throws std::invalid_argument ("glare/eye/aperture_components: ...") for an unknown name, an empty
// list, or a list without "pupil" (the pupil bounds every aperture; there is no PSF without it).
ComponentSelection parse_component_selection(const std::string& names);

// The geometry with only the chosen components' primitives (and untagged ones); pupil, defocus and
// the glare flag unchanged.
ApertureGeometry keep_components(const ApertureGeometry& geometry, const ComponentSelection& selection);

}  // namespace glarelab
