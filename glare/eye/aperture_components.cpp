#include "glare/eye/aperture_components.h"

#include <sstream>
#include <stdexcept>

namespace glarelab {

const char* aperture_component_name(ApertureComponent component) {
  switch (component) {
    case ApertureComponent::unspecified: return "unspecified";
    case ApertureComponent::lens: return "lens";
    case ApertureComponent::gratings: return "gratings";
    case ApertureComponent::vitreous: return "vitreous";
    case ApertureComponent::cornea: return "cornea";
    case ApertureComponent::retina: return "retina";
    case ApertureComponent::lids: return "lids";
    case ApertureComponent::lashes: return "lashes";
  }
  return "unknown";
}

ComponentSelection parse_component_selection(const std::string& names) {
  ComponentSelection selection;
  bool pupil = false;
  std::istringstream list(names);
  std::string name;
  while (std::getline(list, name, ',')) {
    if (name == "pupil") {
      pupil = true;
    } else if (name == "all") {
      pupil = true;
      for (ApertureComponent c : {ApertureComponent::lens, ApertureComponent::gratings, ApertureComponent::vitreous,
                                  ApertureComponent::cornea, ApertureComponent::retina, ApertureComponent::lids,
                                  ApertureComponent::lashes})
        selection.kept.insert(c);
    } else if (name == "lashes") {
      selection.kept.insert(ApertureComponent::lids);
      selection.kept.insert(ApertureComponent::lashes);
    } else {
      bool known = false;
      for (ApertureComponent c : {ApertureComponent::lens, ApertureComponent::gratings, ApertureComponent::vitreous,
                                  ApertureComponent::cornea, ApertureComponent::retina})
        if (name == aperture_component_name(c)) {
          selection.kept.insert(c);
          known = true;
        }
      if (!known)
        throw std::invalid_argument("glare/eye/aperture_components: unknown component '" + name +
                                    "' (expected pupil, lens, gratings, vitreous, cornea, retina, lashes or all)");
    }
  }
  if (!pupil)
    throw std::invalid_argument("glare/eye/aperture_components: '" + names +
                                "' leaves out the pupil, which bounds every aperture; list pupil first");
  return selection;
}

ApertureGeometry keep_components(const ApertureGeometry& geometry, const ComponentSelection& selection) {
  const auto kept = [&](ApertureComponent c) { return c == ApertureComponent::unspecified || selection.kept.count(c) > 0; };
  ApertureGeometry out;
  out.pupil_diameter_mm = geometry.pupil_diameter_mm;
  out.defocus_dioptres = geometry.defocus_dioptres;
  out.glare_enabled = geometry.glare_enabled;
  for (const ApertureDisc& disc : geometry.discs)
    if (kept(disc.component)) out.discs.push_back(disc);
  for (const ApertureLine& line : geometry.lines)
    if (kept(line.component)) out.lines.push_back(line);
  for (const AperturePolygon& polygon : geometry.polygons)
    if (kept(polygon.component)) out.polygons.push_back(polygon);
  return out;
}

}  // namespace glarelab
