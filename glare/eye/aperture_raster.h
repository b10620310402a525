#pragma once
// CPU rasteriser of an ApertureGeometry into an N x N transmittance grid. The GPU path draws the
// same geometry with the same coverage rule, stated here exactly so both agree sample for sample:
//
// Grid: N x N pixels of dx = aperture_width_mm / N. Pixel (i, j), column i, row j (row 0 at the
// top), has its centre at x = (i - N/2) dx, y = (N/2 - j) dx, so the optical axis is the centre
// of pixel (N/2, N/2), the same pixel the PSF's DC term lands on.
// Supersampling s >= 2: sub-sample (a, b), a, b in 0..s-1, of pixel (i, j) is the point
//   x = (i - N/2 - 1/2 + (a + 1/2) / s) dx,   y = (N/2 - j + 1/2 - (b + 1/2) / s) dx.
// Sub-sample value = [x^2 + y^2 <= (pupil_diameter_mm / 2)^2] * product of the transmittances of
// every primitive that contains the point, where
//   disc:    (x - cx)^2 + (y - cy)^2 <= r^2;
//   line:    distance from the point to the segment (x0,y0)-(x1,y1) <= width / 2;
//   polygon: even-odd rule (a horizontal ray to +x crosses the edges an odd number of times;
//            an edge counts when exactly one of its end points has y > point y).
// Pixel value = mean of its s^2 sub-sample values.
#include <complex>
#include <limits>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "glare/wave/fresnel.h"

namespace glarelab {

struct ApertureRasterOptions {
  int grid_px = 512;                // N (any even size; the FFT prefers powers of two)
  double aperture_width_mm = 10.0;  // side of the square the grid covers
  int supersampling = 2;            // s, at least 2
  // Threads sharing the pixel rows. Each pixel row is computed exactly as by one thread, so the
  // grid is the same, bit for bit, whatever the count.
  int threads = 1;
};

struct ApertureGrid {
  int grid_px = 0;
  double aperture_width_mm = 0.0;
  std::vector<double> transmittance;  // row-major, row 0 at the top, values in [0, 1]
  // Rows outside [rows_written_first, rows_written_last] hold 0: rasterise_aperture writes only the
  // pupil's rows and, reusing a grid, clears only the rows its last call wrote (not all N x N
  // values). Code that writes `transmittance` itself must widen the range (or leave the whole grid
  // marked, as a default-constructed one is).
  int rows_written_first = 0, rows_written_last = std::numeric_limits<int>::max();
  double pixel_mm() const { return aperture_width_mm / grid_px; }
};

// Throws std::invalid_argument (naming "glare/eye/aperture_raster") for N < 2 or odd, width <= 0, s < 2.
ApertureGrid rasterise_aperture(const ApertureGeometry& geometry, const ApertureRasterOptions& options);
// The same into `grid`, reusing its storage (no allocation when it already holds N x N values).
void rasterise_aperture(const ApertureGeometry& geometry, const ApertureRasterOptions& options, ApertureGrid& grid);

// The complex aperture A(x, y) * exp(i phi(r)) the FFT takes, with phi = pi c r^2 evaluated at pixel
// centres (glare/wave/fresnel.h gives c). c = 0 leaves a real aperture.
std::vector<std::complex<double>> apply_quadratic_phase(const ApertureGrid& grid, double coefficient_per_m2);

}  // namespace glarelab
