#include "glare/eye/aperture_raster.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <span>
#include <utility>
#include <vector>

#include "core/parallel_for.h"

namespace glarelab {
namespace {

double distance_squared_to_segment(double px, double py, const ApertureLine& line) {
  const double dx = line.x1_mm - line.x0_mm;
  const double dy = line.y1_mm - line.y0_mm;
  const double length2 = dx * dx + dy * dy;
  double t = 0.0;
  if (length2 > 0.0) t = std::clamp(((px - line.x0_mm) * dx + (py - line.y0_mm) * dy) / length2, 0.0, 1.0);
  const double ex = line.x0_mm + t * dx - px;
  const double ey = line.y0_mm + t * dy - py;
  return ex * ex + ey * ey;
}

// The x of every edge of the polygon that crosses the horizontal line at py (the edges
// the even-odd rule counts), in edge order.
void edge_crossings(double py, const std::vector<double>& vertices, std::vector<double>& crossings) {
  crossings.clear();
  const std::size_t count = vertices.size() / 2;
  for (std::size_t k = 0, previous = count - 1; k < count; previous = k++) {
    const double xk = vertices[2 * k], yk = vertices[2 * k + 1];
    const double xp = vertices[2 * previous], yp = vertices[2 * previous + 1];
    if ((yk > py) != (yp > py)) crossings.push_back(xk + (py - yk) * (xp - xk) / (yp - yk));
  }
}

// An x interval of the row at y that holds every point within width / 2 of the line's segment,
// with a margin of one sub-sample (`margin_mm`): a point (x, y) that near the segment is within
// width / 2 of a segment point S, so |S.y - y| <= width / 2 and |S.x - x| <= width / 2. The span is
// therefore the x range of the segment points whose y lies within width / 2 + margin of the row,
// widened by width / 2 + margin. For a long, thin grating line this is a few sub-samples where its
// bounding box is the line's whole x extent. Empty (first > second) when no point can be that near.
std::pair<double, double> line_row_span(const ApertureLine& line, double y, double margin_mm) {
  const double reach = 0.5 * line.width_mm + margin_mm;
  const double dy = line.y1_mm - line.y0_mm;
  double t0 = 0.0, t1 = 1.0;
  if (dy != 0.0) {
    const double ta = (y - reach - line.y0_mm) / dy, tb = (y + reach - line.y0_mm) / dy;
    t0 = std::max(0.0, std::min(ta, tb));
    t1 = std::min(1.0, std::max(ta, tb));
    if (t0 > t1) return {1.0, 0.0};
  } else if (std::abs(line.y0_mm - y) > reach) {
    return {1.0, 0.0};
  }
  const double dx = line.x1_mm - line.x0_mm;
  const double xa = line.x0_mm + t0 * dx, xb = line.x0_mm + t1 * dx;
  return {std::min(xa, xb) - reach, std::max(xa, xb) + reach};
}

// Axis-aligned bounds of a primitive, millimetres.
struct Bounds {
  double x_min, x_max, y_min, y_max;
};

// Indices of primitives per pixel row: row r's are indices[start[r], start[r + 1]), ascending.
struct RowLists {
  std::vector<int> start, indices;
  std::span<const int> of(int row) const {
    const auto first = static_cast<std::size_t>(start[static_cast<std::size_t>(row)]);
    const auto last = static_cast<std::size_t>(start[static_cast<std::size_t>(row) + 1]);
    return {indices.data() + first, last - first};
  }
};

// Each primitive k (bounds[k]) listed on the pixel rows [first, last] = rows_of(bounds[k]) (rows
// counted from the first pixel row rasterised; an empty range lists it nowhere).
template <typename RowsOf>
RowLists list_per_row(const std::vector<Bounds>& bounds, int rows, const RowsOf& rows_of) {
  RowLists lists;
  lists.start.assign(static_cast<std::size_t>(rows) + 1, 0);
  for (const Bounds& b : bounds) {
    const auto [first, last] = rows_of(b);
    for (int row = first; row <= last; ++row) ++lists.start[static_cast<std::size_t>(row) + 1];
  }
  for (int row = 0; row < rows; ++row) lists.start[static_cast<std::size_t>(row) + 1] += lists.start[static_cast<std::size_t>(row)];
  lists.indices.resize(static_cast<std::size_t>(lists.start.back()));
  std::vector<int> next(lists.start.begin(), lists.start.end() - 1);
  for (std::size_t k = 0; k < bounds.size(); ++k) {
    const auto [first, last] = rows_of(bounds[k]);
    for (int row = first; row <= last; ++row)
      lists.indices[static_cast<std::size_t>(next[static_cast<std::size_t>(row)]++)] = static_cast<int>(k);
  }
  return lists;
}

// The options' and polygons' preconditions (std::invalid_argument naming the one broken).
void check_raster_input(const ApertureGeometry& geometry, const ApertureRasterOptions& options) {
  const int n = options.grid_px;
  const int s = options.supersampling;
  if (n < 2 || n % 2 != 0) throw std::invalid_argument("glare/eye/aperture_raster: grid size must be even and >= 2");
  if (!(options.aperture_width_mm > 0.0)) throw std::invalid_argument("glare/eye/aperture_raster: aperture width must be > 0 mm");
  if (s < 2) throw std::invalid_argument("glare/eye/aperture_raster: supersampling must be at least 2");
  for (const auto& polygon : geometry.polygons) {
    if (polygon.vertices_mm.size() < 6 || polygon.vertices_mm.size() % 2 != 0)
      throw std::invalid_argument("glare/eye/aperture_raster: a polygon needs at least 3 (x, y) vertices");
  }
}

// An N x N grid of zeros: allocated when the size changed, else only the rows the last call wrote
// are cleared.
void clear_for_rasterising(ApertureGrid& grid, int n) {
  const std::size_t count = static_cast<std::size_t>(n) * n;
  if (grid.grid_px != n || grid.transmittance.size() != count) {
    grid.transmittance.assign(count, 0.0);
  } else if (grid.rows_written_first <= grid.rows_written_last) {
    // A reused grid: only the rows the last call wrote can hold anything but 0 (8 MB of doubles
    // cleared per frame at N = 1024 otherwise).
    const int first = std::max(0, grid.rows_written_first), last = std::min(n - 1, grid.rows_written_last);
    if (first <= last)
      std::fill(grid.transmittance.begin() + static_cast<std::ptrdiff_t>(first) * n,
                grid.transmittance.begin() + static_cast<std::ptrdiff_t>(last + 1) * n, 0.0);
  }
}

// The bounds of each disc, line (widened by half its width) and polygon, in the geometry's order.
void primitive_bounds(const ApertureGeometry& geometry, std::vector<Bounds>& disc_bounds,
                      std::vector<Bounds>& line_bounds, std::vector<Bounds>& polygon_bounds) {
  for (const auto& d : geometry.discs)
    disc_bounds.push_back({d.centre_x_mm - d.radius_mm, d.centre_x_mm + d.radius_mm, d.centre_y_mm - d.radius_mm,
                           d.centre_y_mm + d.radius_mm});
  for (const auto& l : geometry.lines) {
    const double w = 0.5 * l.width_mm;
    line_bounds.push_back({std::min(l.x0_mm, l.x1_mm) - w, std::max(l.x0_mm, l.x1_mm) + w,
                           std::min(l.y0_mm, l.y1_mm) - w, std::max(l.y0_mm, l.y1_mm) + w});
  }
  for (const auto& p : geometry.polygons) {
    Bounds b{p.vertices_mm[0], p.vertices_mm[0], p.vertices_mm[1], p.vertices_mm[1]};
    for (std::size_t k = 0; k + 1 < p.vertices_mm.size(); k += 2) {
      b.x_min = std::min(b.x_min, p.vertices_mm[k]);
      b.x_max = std::max(b.x_max, p.vertices_mm[k]);
      b.y_min = std::min(b.y_min, p.vertices_mm[k + 1]);
      b.y_max = std::max(b.y_max, p.vertices_mm[k + 1]);
    }
    polygon_bounds.push_back(b);
  }
}

}  // namespace

ApertureGrid rasterise_aperture(const ApertureGeometry& geometry, const ApertureRasterOptions& options) {
  ApertureGrid grid;
  rasterise_aperture(geometry, options, grid);
  return grid;
}

void rasterise_aperture(const ApertureGeometry& geometry, const ApertureRasterOptions& options, ApertureGrid& grid) {
  check_raster_input(geometry, options);
  const int n = options.grid_px;
  const int s = options.supersampling;
  clear_for_rasterising(grid, n);
  grid.grid_px = n;
  grid.aperture_width_mm = options.aperture_width_mm;
  const double dx = grid.pixel_mm();
  const double sub = dx / s;
  const int sub_n = n * s;
  const double half = n / 2;
  const double pupil_r2 = 0.25 * geometry.pupil_diameter_mm * geometry.pupil_diameter_mm;
  // Sub-sample column a_global = i s + a lies at x = (a_global + 1/2) sub - (N/2 + 1/2) dx.
  auto sub_x = [&](int column) { return (column + 0.5) * sub - (half + 0.5) * dx; };
  auto sub_y = [&](int row) { return (half + 0.5) * dx - (row + 0.5) * sub; };
  // Inverse of sub_x for the column range of a bound (widened by one, the exact test decides).
  auto column_range = [&](double x_min, double x_max) {
    const int first = std::max(0, static_cast<int>(std::floor((x_min + (half + 0.5) * dx) / sub - 0.5)) - 1);
    const int last = std::min(sub_n - 1, static_cast<int>(std::ceil((x_max + (half + 0.5) * dx) / sub - 0.5)) + 1);
    return std::pair<int, int>{first, last};
  };

  std::vector<Bounds> disc_bounds, line_bounds, polygon_bounds;
  primitive_bounds(geometry, disc_bounds, line_bounds, polygon_bounds);

  // Only the sub-samples inside the pupil's bounding square can be non-zero: everywhere else the
  // pupil test gives 0 and every primitive multiplies that 0 by a transmittance in [0, 1], so those
  // rows and columns are skipped (the grid stays 0 there, the same values the full loop would give).
  // The range is widened by one sub-sample; the exact pupil test decides inside it.
  const double pupil_r = std::sqrt(pupil_r2);
  // Plain ints, not a structured binding: the lambdas below use them, and capturing a structured
  // binding is C++20 that clang accepts only from version 16 (the fuzz build uses clang).
  const std::pair<int, int> pupil_columns = column_range(-pupil_r, pupil_r);
  const int pupil_first_column = pupil_columns.first, pupil_last_column = pupil_columns.second;
  // sub_y is sub_x mirrored: row r lies at y = -sub_x(r), so the row range is the column range of [-r, r].
  const int pupil_first_row = pupil_first_column, pupil_last_row = pupil_last_column;
  const int first_pixel_row = pupil_first_row / s, last_pixel_row = pupil_last_row / s;

  // The discs (the eye model's lens particles: over a thousand) and the lines (its lashes and
  // fibres: over a thousand with a wide pupil) listed per pixel row whose sub-rows their bounds may
  // meet, each list in the primitives' order, so that a sub-row visits only its few primitives
  // instead of testing every one's bounds (most of the rasteriser's time at N = 512 and 1024). The
  // bounds test below still decides, so each sub-sample sees the same primitives, in the same order,
  // as the loops over all of them: the grid is the same, bit for bit.
  const int pixel_rows = std::max(0, last_pixel_row - first_pixel_row + 1);
  // Sub-row r lies at y = (N/2 + 1/2) dx - (r + 1/2) sub: the sub-rows of [y_min, y_max], widened by one.
  const auto pixel_rows_of = [&](const Bounds& b) {
    const double top = (half + 0.5) * dx;
    // Clamped in double first: a primitive far off the grid must not overflow the int.
    const auto sub_row_at = [&](double position) { return static_cast<int>(std::clamp(position, -2.0, sub_n + 1.0)); };
    const int first_sub = sub_row_at(std::floor((top - b.y_max) / sub - 0.5)) - 1;
    const int last_sub = sub_row_at(std::ceil((top - b.y_min) / sub - 0.5)) + 1;
    const int first = std::max(first_pixel_row, std::max(0, first_sub) / s);
    const int last = std::min(last_pixel_row, std::min(sub_n - 1, last_sub) / s);
    return std::pair<int, int>{first - first_pixel_row, last - first_pixel_row};
  };
  const RowLists disc_lists = list_per_row(disc_bounds, pixel_rows, pixel_rows_of);
  const RowLists line_lists = list_per_row(line_bounds, pixel_rows, pixel_rows_of);

  // One row of sub-samples at a time: pupil test, then each primitive whose bounds meet the row
  // multiplies its transmittance into the sub-samples it contains. Pixel rows are independent and
  // shared among threads.
  const double inverse_samples = 1.0 / (s * s);
  const auto rasterise_pixel_rows = [&](int first, int last) {
    std::vector<double> row_values(static_cast<std::size_t>(sub_n), 0.0);
    std::vector<double> crossings;
    const auto clip = [&](std::pair<int, int> range) {
      return std::pair<int, int>{std::max(range.first, pupil_first_column), std::min(range.second, pupil_last_column)};
    };
    for (int sub_row = (first_pixel_row + first) * s; sub_row < (first_pixel_row + last) * s; ++sub_row) {
      const double y = sub_y(sub_row);
      for (int column = pupil_first_column; column <= pupil_last_column; ++column) {
        const double x = sub_x(column);
        row_values[static_cast<std::size_t>(column)] = (x * x + y * y <= pupil_r2) ? 1.0 : 0.0;
      }
      const int list_row = sub_row / s - first_pixel_row;
      for (const int listed : disc_lists.of(list_row)) {
        const auto k = static_cast<std::size_t>(listed);
        const Bounds& b = disc_bounds[k];
        if (y < b.y_min || y > b.y_max) continue;
        const auto& disc = geometry.discs[k];
        const double ey = y - disc.centre_y_mm;
        // The disc's chord on this row, widened by one sub-sample on each side (column_range adds
        // one more): no sub-sample outside it can pass the exact test below, so the grid is the one
        // the whole bounding box would give, bit for bit.
        const double half_chord = std::sqrt(std::max(0.0, disc.radius_mm * disc.radius_mm - ey * ey)) + sub;
        const auto [first_column, last_column] =
            clip(column_range(disc.centre_x_mm - half_chord, disc.centre_x_mm + half_chord));
        for (int column = first_column; column <= last_column; ++column) {
          const double ex = sub_x(column) - disc.centre_x_mm;
          if (ex * ex + ey * ey <= disc.radius_mm * disc.radius_mm)
            row_values[static_cast<std::size_t>(column)] *= disc.transmittance;
        }
      }
      for (const int listed : line_lists.of(list_row)) {
        const auto k = static_cast<std::size_t>(listed);
        const Bounds& b = line_bounds[k];
        if (y < b.y_min || y > b.y_max) continue;
        const auto& line = geometry.lines[k];
        const double w2 = 0.25 * line.width_mm * line.width_mm;
        const auto [x_min, x_max] = line_row_span(line, y, sub);
        if (x_min > x_max) continue;
        const auto [first_column, last_column] = clip(column_range(x_min, x_max));
        for (int column = first_column; column <= last_column; ++column) {
          if (distance_squared_to_segment(sub_x(column), y, line) <= w2)
            row_values[static_cast<std::size_t>(column)] *= line.transmittance;
        }
      }
      for (std::size_t k = 0; k < geometry.polygons.size(); ++k) {
        const Bounds& b = polygon_bounds[k];
        if (y < b.y_min || y > b.y_max) continue;
        const auto& polygon = geometry.polygons[k];
        // The even-odd test per sub-sample, with the edge crossings of this row found once: the same
        // x_cross values and comparisons as a per-point ray test, in a scanline.
        edge_crossings(y, polygon.vertices_mm, crossings);
        const auto [first_column, last_column] = clip(column_range(b.x_min, b.x_max));
        for (int column = first_column; column <= last_column; ++column) {
          const double x = sub_x(column);
          bool inside = false;
          for (double x_cross : crossings)
            if (x < x_cross) inside = !inside;
          if (inside) row_values[static_cast<std::size_t>(column)] *= polygon.transmittance;
        }
      }
      double* pixel_row = &grid.transmittance[static_cast<std::size_t>(sub_row / s) * n];
      for (int column = pupil_first_column; column <= pupil_last_column; ++column)
        pixel_row[column / s] += row_values[static_cast<std::size_t>(column)] * inverse_samples;
    }
  };
  if (pupil_first_column <= pupil_last_column)
    parallel_chunks(last_pixel_row - first_pixel_row + 1, options.threads, rasterise_pixel_rows);
  grid.rows_written_first = first_pixel_row;
  grid.rows_written_last = pupil_first_column <= pupil_last_column ? last_pixel_row : first_pixel_row - 1;
}

std::vector<std::complex<double>> apply_quadratic_phase(const ApertureGrid& grid, double coefficient_per_m2) {
  const int n = grid.grid_px;
  const double dx_m = grid.pixel_mm() * 1e-3;
  std::vector<std::complex<double>> field(grid.transmittance.size());
  for (int j = 0; j < n; ++j) {
    const double y_m = (n / 2 - j) * dx_m;
    for (int i = 0; i < n; ++i) {
      const double x_m = (i - n / 2) * dx_m;
      const std::size_t index = static_cast<std::size_t>(j) * n + i;
      const double a = grid.transmittance[index];
      if (coefficient_per_m2 == 0.0 || a == 0.0) {
        field[index] = {a, 0.0};
      } else {
        field[index] = std::polar(a, quadratic_phase_rad(coefficient_per_m2, x_m * x_m + y_m * y_m));
      }
    }
  }
  return field;
}

}  // namespace glarelab
