#pragma once
// The coverage rule of glare/eye/aperture_raster.h, one sub-sample at a time over the whole grid,
// without the rasteriser's shortcuts (pupil bounding square, row spans of discs and lines, scanline
// polygon crossings, threads): the same expressions, products and sums in the same order, so the
// rasteriser must equal it bit for bit. Each sub-sample adds value * (1 / s^2), as the rasteriser
// forms the mean (for s = 2 the same as value / s^2).
#include <algorithm>
#include <cstddef>
#include <vector>

#include "glare/eye/aperture_geometry.h"

namespace glarelab::test {

inline std::vector<double> rasterise_by_the_rule(const ApertureGeometry& geometry, int n, double width_mm, int s) {
  std::vector<double> grid(static_cast<std::size_t>(n) * n, 0.0);
  const double dx = width_mm / n, r2 = 0.25 * geometry.pupil_diameter_mm * geometry.pupil_diameter_mm;
  const double inverse_samples = 1.0 / (s * s);
  for (int row = 0; row < n * s; ++row)
    for (int column = 0; column < n * s; ++column) {
      const double x = (column + 0.5) * (dx / s) - (n / 2 + 0.5) * dx;
      const double y = (n / 2 + 0.5) * dx - (row + 0.5) * (dx / s);
      double value = (x * x + y * y <= r2) ? 1.0 : 0.0;
      for (const auto& d : geometry.discs)
        if ((x - d.centre_x_mm) * (x - d.centre_x_mm) + (y - d.centre_y_mm) * (y - d.centre_y_mm) <= d.radius_mm * d.radius_mm)
          value *= d.transmittance;
      for (const auto& l : geometry.lines) {
        const double lx = l.x1_mm - l.x0_mm, ly = l.y1_mm - l.y0_mm, length2 = lx * lx + ly * ly;
        const double t = length2 > 0.0 ? std::clamp(((x - l.x0_mm) * lx + (y - l.y0_mm) * ly) / length2, 0.0, 1.0) : 0.0;
        const double ex = l.x0_mm + t * lx - x, ey = l.y0_mm + t * ly - y;
        if (ex * ex + ey * ey <= 0.25 * l.width_mm * l.width_mm) value *= l.transmittance;
      }
      for (const auto& p : geometry.polygons) {
        const auto& v = p.vertices_mm;
        const std::size_t count = v.size() / 2;
        bool inside = false;
        for (std::size_t k = 0, previous = count - 1; k < count; previous = k++)
          if ((v[2 * k + 1] > y) != (v[2 * previous + 1] > y) &&
              x < v[2 * k] + (y - v[2 * k + 1]) * (v[2 * previous] - v[2 * k]) / (v[2 * previous + 1] - v[2 * k + 1]))
            inside = !inside;
        if (inside) value *= p.transmittance;
      }
      grid[static_cast<std::size_t>(row / s) * n + column / s] += value * inverse_samples;
    }
  return grid;
}

}  // namespace glarelab::test
