#pragma once
// Static scatterers projected onto the pupil plane (Ritschel et al. 2009, sections 3.1 and 3.5).
//  - Cornea: the flat cells between the collagen fibrils (15 um, 3-5% of the volume) scatter 25-30%
//    of the intraocular straylight without temporal change: large (against the fibrils), sparse,
//    static particles.
//  - Retina: its forward scattering is approximated, after Navarro 1985 and van den Berg et al. 2005,
//    by fewer and larger particles.
// Both are uniform over a disc around the axis and never move.
#include <cstdint>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/eye/eye_parameters.h"

namespace glarelab {

class CorneaRetinaParticles {
 public:
  CorneaRetinaParticles(const EyeParameters& parameters, std::uint64_t seed);

  const std::vector<ApertureDisc>& cornea() const { return cornea_; }
  const std::vector<ApertureDisc>& retina() const { return retina_; }

 private:
  std::vector<ApertureDisc> cornea_;
  std::vector<ApertureDisc> retina_;
};

}  // namespace glarelab
