#include "glare/refraction/chromatic_eye.h"

#include <stdexcept>
#include <string>

namespace glarelab {

double chromatic_refraction_dioptres(double wavelength_nm) {
  const double wavelength_um = wavelength_nm * 1e-3;
  if (!(wavelength_um > kThibosC_um))
    throw std::invalid_argument("glare/refraction/chromatic_eye: wavelength " + std::to_string(wavelength_nm) +
                                " nm is at or below the pole of Thibos' fit (214.1 nm)");
  return kThibosP_dioptres - kThibosQ_dioptre_um / (wavelength_um - kThibosC_um);
}

double chromatic_power_excess_dioptres(double wavelength_nm, double reference_nm) {
  return chromatic_refraction_dioptres(reference_nm) - chromatic_refraction_dioptres(wavelength_nm);
}

}  // namespace glarelab
