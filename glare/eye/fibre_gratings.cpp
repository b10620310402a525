#include "glare/eye/fibre_gratings.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace glarelab {

double grating_period_um(double wavelength_nm, double halo_degrees) {
  // Grating equation, first order at normal incidence: period sin(theta) = lambda.
  return wavelength_nm * 1e-3 / std::sin(halo_degrees * std::numbers::pi / 180.0);
}

void add_radial_fibre_gratings(ApertureGeometry& geometry, const FibreGratingOptions& options) {
  if (!(options.inner_radius_mm > 0.0) || !(options.outer_radius_mm > options.inner_radius_mm))
    throw std::invalid_argument("glare/eye/fibre_gratings: need 0 < inner radius < outer radius");
  if (!(options.period_um > 0.0) || !(options.duty > 0.0) || !(options.duty < 1.0))
    throw std::invalid_argument("glare/eye/fibre_gratings: need period > 0 and 0 < duty < 1");
  const double period_mm = options.period_um * 1e-3;
  const int rings = static_cast<int>(std::ceil(std::log(options.outer_radius_mm / options.inner_radius_mm) / std::log(1.05)));
  const double ratio = std::pow(options.outer_radius_mm / options.inner_radius_mm, 1.0 / rings);
  double inner = options.inner_radius_mm;
  for (int ring = 0; ring < rings; ++ring) {
    const double outer = inner * ratio;
    const double middle = 0.5 * (inner + outer);
    const int lines = static_cast<int>(std::lround(2.0 * std::numbers::pi * middle / period_mm));
    // Offset alternate rings by half a line so line ends do not align radially.
    const double offset = (ring % 2) * 0.5;
    for (int k = 0; k < lines; ++k) {
      const double angle = 2.0 * std::numbers::pi * (k + offset) / lines;
      const double c = std::cos(angle), s = std::sin(angle);
      geometry.lines.push_back({inner * c, inner * s, outer * c, outer * s, options.duty * period_mm, options.transmittance,
                                ApertureComponent::gratings});
    }
    inner = outer;
  }
}

}  // namespace glarelab
