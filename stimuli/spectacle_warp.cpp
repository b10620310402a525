#include "stimuli/spectacle_warp.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "core/parallel_for.h"
#include "stimuli/float4.h"
#include "stimuli/spectacle_warp_span.h"

namespace glarelab {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

[[noreturn]] void refuse(const std::string& message) { throw std::invalid_argument("stimuli/spectacle_warp: " + message); }

std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void validate_frame(const SpectacleFrame& frame) {
  if (frame.width_px <= 0 || frame.height_px <= 0)
    refuse("the frame has no pixels (" + std::to_string(frame.width_px) + " x " + std::to_string(frame.height_px) + ")");
  if (!(frame.degrees_per_pixel_at_centre > 0.0 && frame.degrees_per_pixel_at_centre <= 10.0))
    refuse("degrees_per_pixel_at_centre must lie in (0, 10] (got " + number(frame.degrees_per_pixel_at_centre) + ")");
}

void validate_scene_distance(const SpectacleLens& lens, const std::optional<double>& scene_distance_mm) {
  if (!scene_distance_mm) return;
  const double lens_mm = lens.spec().vertex_distance_mm + lens.centre_thickness_m() * 1000.0;
  if (!(*scene_distance_mm > lens_mm) || !std::isfinite(*scene_distance_mm))
    refuse("scene_distance_mm " + number(*scene_distance_mm) + " must lie beyond the lens' front (" + number(lens_mm) +
           " mm from the cornea)");
}

double pixel_scale(const SpectacleFrame& frame) {
  return 2.0 * std::tan(0.5 * frame.degrees_per_pixel_at_centre / kDegPerRad);  // tangent per pixel
}

// The scene pixel that the line of sight through `pixel` shows; refuses a line of sight the lens
// does not pass.
glm::dvec2 trace_pixel(const SpectacleLens& lens, const SpectacleFrame& frame, glm::dvec2 pixel, double wavelength_nm,
                       const std::optional<double>& scene_distance_mm) {
  const glm::dvec3 gaze = frame.direction(pixel);
  const LensRay ray = lens.trace_from_eye(gaze, wavelength_nm);
  if (!ray.through() || !(ray.direction.z > 0.0)) {
    const double right_deg = std::atan2(gaze.x, gaze.z) * kDegPerRad, up_deg = std::atan2(gaze.y, gaze.z) * kDegPerRad;
    refuse("the frame's line of sight at pixel (" + number(pixel.x) + ", " + number(pixel.y) + "), " + number(right_deg) +
           " deg right and " + number(up_deg) + " deg up, " +
           (ray.through() ? std::string("leaves the lens away from the scene") : describe(ray.outcome)) + " (diameter_mm " +
           number(lens.spec().diameter_mm) + "): the lens does not cover this field of view");
  }
  if (!scene_distance_mm) return frame.pixel(ray.direction);
  const double plane_z_m = lens.cornea_z_m() + *scene_distance_mm * 1e-3;
  const glm::dvec3 point = ray.origin_m + ray.direction * ((plane_z_m - ray.origin_m.z) / ray.direction.z);
  return frame.pixel(point);
}

void validate_wavelength(double wavelength_nm) {
  if (!(wavelength_nm >= 360.0 && wavelength_nm <= 830.0))
    refuse("wavelength " + number(wavelength_nm) + " nm lies outside 360-830 nm, where the dispersion formula is not extrapolated");
}

// Bilinear sample of one channel at a continuous pixel position (pixel i's centre at i); outside
// the outermost pixel centres the scene is `outside`.
float sample_bilinear(const ImageRGBA& scene, glm::dvec2 at, int channel, float outside) {
  const double x = at.x, y = at.y;
  if (!(x >= 0.0 && y >= 0.0 && x <= scene.width_px - 1.0 && y <= scene.height_px - 1.0)) return outside;
  const int x0 = std::min(static_cast<int>(x), scene.width_px - 2 < 0 ? 0 : scene.width_px - 2);
  const int y0 = std::min(static_cast<int>(y), scene.height_px - 2 < 0 ? 0 : scene.height_px - 2);
  const int x1 = std::min(x0 + 1, scene.width_px - 1), y1 = std::min(y0 + 1, scene.height_px - 1);
  const double fx = x - x0, fy = y - y0;
  const double top = (1.0 - fx) * scene.pixel(x0, y0)[channel] + fx * scene.pixel(x1, y0)[channel];
  const double bottom = (1.0 - fx) * scene.pixel(x0, y1)[channel] + fx * scene.pixel(x1, y1)[channel];
  return static_cast<float>((1.0 - fy) * top + fy * bottom);
}

// Bilinear interpolation of the vertex positions (grid_vertices per side, from the first to the
// last pixel centre) at a pixel, the row's cell found once per row.
class GridInterpolation {
 public:
  struct Row {
    int cell = 0;
    double fraction = 0.0;
  };
  GridInterpolation(const SpectacleFrame& frame, std::vector<glm::dvec2> vertex, int grid_vertices)
      : vertex_(std::move(vertex)),
        g_(grid_vertices),
        step_x_((frame.width_px - 1.0) / (grid_vertices - 1)),
        step_y_((frame.height_px - 1.0) / (grid_vertices - 1)) {}
  Row row(int y) const { return locate(y, step_y_); }
  Row column(int x) const { return locate(x, step_x_); }
  glm::dvec2 at(const Row& row, int x) const { return at(row, column(x)); }
  // The row's positions at each vertex column, (1 - fy) top + fy bottom, into edge[0 .. g).
  void row_edges(const Row& row, glm::dvec2* edge) const {
    const std::size_t top = static_cast<std::size_t>(row.cell) * g_, bottom = top + g_;
    for (int i = 0; i < g_; ++i) edge[i] = (1.0 - row.fraction) * vertex_[top + i] + row.fraction * vertex_[bottom + i];
  }
  // Grids of one frame and vertex count share their rows and columns: found once, used for each.
  glm::dvec2 at(const Row& row, const Row& column) const {
    const std::size_t top = static_cast<std::size_t>(row.cell) * g_ + column.cell, bottom = top + g_;
    const double fx = column.fraction, fy = row.fraction;
    return (1.0 - fy) * ((1.0 - fx) * vertex_[top] + fx * vertex_[top + 1]) + fy * ((1.0 - fx) * vertex_[bottom] + fx * vertex_[bottom + 1]);
  }

 private:
  Row locate(int pixel, double step) const {
    const double position = step > 0.0 ? pixel / step : 0.0;
    Row out;
    out.cell = std::min(static_cast<int>(position), g_ - 2);
    out.fraction = position - out.cell;
    return out;
  }
  std::vector<glm::dvec2> vertex_;
  int g_;
  double step_x_, step_y_;
};

}  // namespace

glm::dvec3 SpectacleFrame::direction(glm::dvec2 at_px) const {
  const double k = pixel_scale(*this);
  const double u = at_px.x - 0.5 * (width_px - 1), v = 0.5 * (height_px - 1) - at_px.y;
  return glm::normalize(glm::dvec3(u * k, v * k, 1.0));
}

glm::dvec2 SpectacleFrame::pixel(glm::dvec3 dir) const {
  const double k = pixel_scale(*this);
  return glm::dvec2(0.5 * (width_px - 1) + dir.x / (dir.z * k), 0.5 * (height_px - 1) - dir.y / (dir.z * k));
}

std::vector<glm::dvec2> trace_grid_vertices(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm,
                                            int grid_vertices, std::optional<double> scene_distance_mm) {
  validate_frame(frame);
  validate_wavelength(wavelength_nm);
  validate_scene_distance(lens, scene_distance_mm);
  if (grid_vertices < 2) refuse("grid_vertices must be at least 2 (got " + std::to_string(grid_vertices) + ")");
  const int g = grid_vertices;
  // Vertices from the first to the last pixel centre, so every pixel is interpolated, none extrapolated.
  const double step_x = (frame.width_px - 1.0) / (g - 1), step_y = (frame.height_px - 1.0) / (g - 1);
  std::vector<glm::dvec2> vertex(static_cast<std::size_t>(g) * g);
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i)
      vertex[static_cast<std::size_t>(j) * g + i] =
          trace_pixel(lens, frame, glm::dvec2(i * step_x, j * step_y), wavelength_nm, scene_distance_mm);
  return vertex;
}

SourceMap grid_source_map(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm, int grid_vertices,
                          std::optional<double> scene_distance_mm, int threads) {
  const GridInterpolation grid(frame, trace_grid_vertices(lens, frame, wavelength_nm, grid_vertices, scene_distance_mm), grid_vertices);
  SourceMap map{frame.width_px, frame.height_px, std::vector<glm::dvec2>(static_cast<std::size_t>(frame.width_px) * frame.height_px)};
  parallel_chunks(frame.height_px, threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const GridInterpolation::Row row = grid.row(y);
      for (int x = 0; x < frame.width_px; ++x) map.position_px[static_cast<std::size_t>(y) * frame.width_px + x] = grid.at(row, x);
    }
  });
  return map;
}

SourceMap traced_source_map(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm,
                            std::optional<double> scene_distance_mm, int threads) {
  validate_frame(frame);
  validate_wavelength(wavelength_nm);
  validate_scene_distance(lens, scene_distance_mm);
  SourceMap map{frame.width_px, frame.height_px, std::vector<glm::dvec2>(static_cast<std::size_t>(frame.width_px) * frame.height_px)};
  // Refuse before tracing in parallel, so the message comes from one thread: the corners and edge
  // midpoints first.
  for (double fy : {0.0, 0.5, 1.0})
    for (double fx : {0.0, 0.5, 1.0})
      trace_pixel(lens, frame, glm::dvec2(fx * (frame.width_px - 1), fy * (frame.height_px - 1)), wavelength_nm, scene_distance_mm);
  std::mutex failure_mutex;
  std::exception_ptr failure;
  parallel_chunks(frame.height_px, threads, [&](int first, int last) {
    try {
      for (int y = first; y < last; ++y)
        for (int x = 0; x < frame.width_px; ++x)
          map.position_px[static_cast<std::size_t>(y) * frame.width_px + x] =
              trace_pixel(lens, frame, glm::dvec2(x, y), wavelength_nm, scene_distance_mm);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  });
  if (failure) std::rethrow_exception(failure);
  return map;
}

namespace {

void validate_scene_size(const ImageRGBA& scene, const SpectacleFrame& frame) {
  if (scene.width_px != frame.width_px || scene.height_px != frame.height_px)
    refuse("the scene is " + std::to_string(scene.width_px) + " x " + std::to_string(scene.height_px) + " but the frame " +
           std::to_string(frame.width_px) + " x " + std::to_string(frame.height_px));
}

// The three channels' grids as interpolations.
std::vector<GridInterpolation> channel_grids(const SpectacleWarpGrids& traced) {
  std::vector<GridInterpolation> grids;
  for (int channel = 0; channel < 3; ++channel) grids.emplace_back(traced.frame(), traced.vertices(channel), traced.grid_vertices());
  return grids;
}

// The checks of warp_through_spectacles and the three channels' traced grids.
std::vector<GridInterpolation> channel_grids(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                                             const SpectacleWarpOptions& options) {
  validate_frame(frame);
  validate_scene_size(scene, frame);
  return channel_grids(SpectacleWarpGrids(lens, frame, options));
}

// A bilinear sample of all four channels at a continuous pixel position, in float: the position
// in double (a position off by 1e-12 px moves a value beside a 1e7 : 1 edge by 1e-5 of itself),
// its fractions rounded to float only as the weights, 1 - f taken in double first, so each weight
// keeps float's relative precision and the sum of four non-negative products its 4e-7.
class BilinearSampler {
 public:
  explicit BilinearSampler(const ImageRGBA& scene)
      : scene_(scene),
        last_x_(scene.width_px - 1.0),
        last_y_(scene.height_px - 1.0),
        step_x_(scene.width_px > 1 ? 4 : 0),
        step_y_(scene.height_px > 1 ? 4 * static_cast<std::ptrdiff_t>(scene.width_px) : 0) {}
  bool inside(glm::dvec2 at) const { return at.x >= 0.0 && at.y >= 0.0 && at.x <= last_x_ && at.y <= last_y_; }
  // Within [0, last - margin) on both axes: the cell's corner is the truncated position, no clamp.
  bool clear_of_edges(glm::dvec2 at, double margin) const {
    return at.x >= margin && at.y >= margin && at.x < last_x_ - margin && at.y < last_y_ - margin;
  }
  // Both points beyond the same edge of the scene by more than margin: so is every point between them.
  bool beyond_one_edge(glm::dvec2 a, glm::dvec2 b, double margin) const {
    return (a.x < -margin && b.x < -margin) || (a.y < -margin && b.y < -margin) || (a.x > last_x_ + margin && b.x > last_x_ + margin) ||
           (a.y > last_y_ + margin && b.y > last_y_ + margin);
  }
  // At a position `inside` accepts (the last pixel centre's cell is the one before it).
  Float4 at(glm::dvec2 at) const {
    const int x0 = std::min(static_cast<int>(at.x), std::max(scene_.width_px - 2, 0));
    const int y0 = std::min(static_cast<int>(at.y), std::max(scene_.height_px - 2, 0));
    return blend(scene_.pixel(x0, y0), at.x - x0, at.y - y0);
  }

 private:
  Float4 blend(const float* corner, double fx, double fy) const {
    const Float4 wx0 = Float4::all(static_cast<float>(1.0 - fx)), wx1 = Float4::all(static_cast<float>(fx));
    const Float4 wy0 = Float4::all(static_cast<float>(1.0 - fy)), wy1 = Float4::all(static_cast<float>(fy));
    const Float4 top = wx0 * Float4::load(corner) + wx1 * Float4::load(corner + step_x_);
    const Float4 bottom = wx0 * Float4::load(corner + step_y_) + wx1 * Float4::load(corner + step_y_ + step_x_);
    return wy0 * top + wy1 * bottom;
  }
  const ImageRGBA& scene_;
  double last_x_, last_y_;
  std::ptrdiff_t step_x_, step_y_;
};

// Narrows [f_low, f_high] to the fractions f at which edge + f step lies in [low, high].
void clear_fractions(double edge, double step, double low, double high, double& f_low, double& f_high) {
  if (step > 0.0) {
    f_low = std::max(f_low, (low - edge) / step);
    f_high = std::min(f_high, (high - edge) / step);
  } else if (step < 0.0) {
    f_low = std::max(f_low, (high - edge) / step);
    f_high = std::min(f_high, (low - edge) / step);
  } else if (!(edge >= low && edge <= high)) {
    f_low = std::numeric_limits<double>::infinity();
  }
}

// For each grid cell (row-major, grid_vertices - 1 a side), whether its four vertices lie clear of
// the scene's edges by `margin` for all three channels.
std::vector<bool> clear_grid_cells(const SpectacleWarpGrids& traced, const BilinearSampler& sampler, double margin) {
  const std::size_t g = static_cast<std::size_t>(traced.grid_vertices());
  std::vector<bool> clear((g - 1) * (g - 1), true);
  for (int channel = 0; channel < 3; ++channel)
    for (std::size_t j = 0; j + 1 < g; ++j)
      for (std::size_t i = 0; i + 1 < g; ++i)
        for (const std::size_t vertex : {j * g + i, j * g + i + 1, (j + 1) * g + i, (j + 1) * g + i + 1})
          if (!sampler.clear_of_edges(traced.vertices(channel)[vertex], margin)) clear[j * (g - 1) + i] = false;
  return clear;
}

}  // namespace

ImageRGBA warp_through_spectacles(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                                  const SpectacleWarpOptions& options) {
  ImageRGBA out;
  warp_through_spectacles(scene, lens, frame, options, out);
  return out;
}

void warp_through_spectacles(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                             const SpectacleWarpOptions& options, ImageRGBA& out) {
  validate_frame(frame);
  validate_scene_size(scene, frame);
  warp_through_spectacles(scene, SpectacleWarpGrids(lens, frame, options), options, out);
}

ImageRGBA warp_through_spectacles(const ImageRGBA& scene, const SpectacleWarpGrids& grids, const SpectacleWarpOptions& options) {
  ImageRGBA out;
  warp_through_spectacles(scene, grids, options, out);
  return out;
}

SpectacleWarpGrids::SpectacleWarpGrids(const SpectacleLens& lens, const SpectacleFrame& frame, const SpectacleWarpOptions& options)
    : frame_(frame),
      grid_vertices_(options.grid_vertices),
      wavelengths_nm_(options.wavelengths_nm),
      scene_distance_mm_(options.scene_distance_mm) {
  validate_frame(frame);
  for (double wavelength : options.wavelengths_nm) validate_wavelength(wavelength);
  for (int channel = 0; channel < 3; ++channel)
    vertices_[static_cast<std::size_t>(channel)] =
        trace_grid_vertices(lens, frame, options.wavelengths_nm[static_cast<std::size_t>(channel)], options.grid_vertices,
                            options.scene_distance_mm);
}

bool SpectacleWarpGrids::traced_for(const SpectacleFrame& frame, const SpectacleWarpOptions& options) const {
  return frame.width_px == frame_.width_px && frame.height_px == frame_.height_px &&
         frame.degrees_per_pixel_at_centre == frame_.degrees_per_pixel_at_centre && options.grid_vertices == grid_vertices_ &&
         options.wavelengths_nm == wavelengths_nm_ && options.scene_distance_mm == scene_distance_mm_;
}

SpectacleWarpGridCache::SpectacleWarpGridCache(std::shared_ptr<const SpectacleLens> lens) : lens_(std::move(lens)) {
  if (!lens_) refuse("a grid cache needs a lens");
}

std::shared_ptr<const SpectacleWarpGrids> SpectacleWarpGridCache::grids(const SpectacleFrame& frame, const SpectacleWarpOptions& options) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!grids_ || !grids_->traced_for(frame, options)) grids_ = std::make_shared<const SpectacleWarpGrids>(*lens_, frame, options);
  return grids_;
}

void warp_through_spectacles(const ImageRGBA& scene, const SpectacleWarpGrids& traced, const SpectacleWarpOptions& options,
                             ImageRGBA& out) {
  const SpectacleFrame& frame = traced.frame();
  validate_scene_size(scene, frame);
  if (!traced.traced_for(frame, options))
    refuse("the grids were traced for other wavelengths, grid_vertices or scene_distance_mm than the warp's options");
  const std::vector<GridInterpolation> grids = channel_grids(traced);
  const int width = frame.width_px, g = options.grid_vertices;
  if (&out == &scene) refuse("the output frame must not be the scene");
  if (out.width_px != width || out.height_px != frame.height_px) out = ImageRGBA(width, frame.height_px, 0.0f);
  out.depth.clear();
  std::vector<GridInterpolation::Row> columns(static_cast<std::size_t>(width));
  for (int x = 0; x < width; ++x) columns[static_cast<std::size_t>(x)] = grids[0].column(x);
  const BilinearSampler sampler(scene);
  const float outside_values[4] = {options.outside_cd_m2[0], options.outside_cd_m2[1], options.outside_cd_m2[2], 1.0f};
  const Float4 outside = Float4::load(outside_values);
  const Mask4 red = Mask4::of(true, false, false, false), blue = Mask4::of(false, false, true, false);
  // Margin of the segments taken without per-pixel checks: far above the 1e-13 px by which a
  // position along a segment may round past its ends.
  constexpr double kMarginPx = 1e-6;
  if (!vector_isa_available(options.vector_isa))
    refuse(std::string("this CPU does not run the ") + (options.vector_isa == VectorIsa::avx512 ? "AVX-512" : "AVX2 and FMA") +
           " form of the warp");
  // Each cell's first column (columns' cells never fall along x) and each column's fraction.
  std::vector<int> cell_first(static_cast<std::size_t>(g), width);
  std::vector<double> fraction(static_cast<std::size_t>(width));
  for (int x = width - 1; x >= 0; --x) {
    cell_first[static_cast<std::size_t>(columns[static_cast<std::size_t>(x)].cell)] = x;
    fraction[static_cast<std::size_t>(x)] = columns[static_cast<std::size_t>(x)].fraction;
  }
  for (int i = g - 2; i >= 0; --i) cell_first[static_cast<std::size_t>(i)] = std::min(cell_first[static_cast<std::size_t>(i)], cell_first[static_cast<std::size_t>(i) + 1]);
  // The grid cells whose pixels all lie clear of the scene's edges for every channel: a pixel's
  // position is a bilinear interpolation of its cell's four vertices, a convex combination, so it
  // lies in any box that holds all four (to the 1e-13 px of its rounding, far inside the margin).
  const std::vector<bool> cell_clear = clear_grid_cells(traced, sampler, kMarginPx);
  parallel_chunks(frame.height_px, options.threads, [&](int first, int last) {
    // Per row, each channel's positions at the vertex columns and their steps to the next column:
    // along a row the grid's bilinear interpolation is linear within a cell, so a pixel's position
    // is its cell's left edge plus the column fraction times the step (GridInterpolation::at
    // rearranged; the same to 1e-13 px).
    std::vector<glm::dvec2> edge(3 * static_cast<std::size_t>(g)), step(edge.size());
    std::vector<WarpCellLine> lines(3 * static_cast<std::size_t>(g - 1));
    for (int y = first; y < last; ++y) {
      const GridInterpolation::Row row = grids[0].row(y);
      for (int c = 0; c < 3; ++c) {
        glm::dvec2* e = &edge[static_cast<std::size_t>(c) * g];
        grids[static_cast<std::size_t>(c)].row_edges(row, e);
        for (int i = 0; i + 1 < g; ++i) step[static_cast<std::size_t>(c) * g + i] = e[i + 1] - e[i];
      }
      for (std::size_t i = 0; i + 1 < static_cast<std::size_t>(g); ++i)
        for (std::size_t c = 0; c < 3; ++c) {
          const glm::dvec2 e = edge[c * g + i], s = step[c * g + i];
          lines[3 * i + c] = {e.x, e.y, s.x, s.y};
        }
      const std::size_t band = static_cast<std::size_t>(row.cell) * static_cast<std::size_t>(g - 1);
      for (int i = 0; i + 1 < g;) {
        // A run of cells clear throughout: one call.
        int run_end = i;
        while (run_end + 1 < g && cell_clear[band + static_cast<std::size_t>(run_end)]) ++run_end;
        if (run_end > i) {
          warp_clear_cells(scene.rgba.data(), scene.width_px, scene.height_px, lines.data(), cell_first.data(), i, run_end,
                           fraction.data(), out.pixel(0, y), options.vector_isa);
          i = run_end;
          continue;
        }
        const std::size_t cell = static_cast<std::size_t>(i++);
        const int x_first = cell_first[cell], x_last = cell_first[cell + 1];
        const WarpCellLine* line = &lines[3 * cell];
        if (x_first >= x_last) continue;
        // A cell whose ends lie beyond the same edge for every channel shows the outside throughout.
        bool all_beyond = true;
        for (std::size_t c = 0; c < 3; ++c)
          all_beyond = all_beyond && sampler.beyond_one_edge(edge[c * g + cell], edge[c * g + cell + 1], kMarginPx);
        if (all_beyond) {
          float* pixel = out.pixel(x_first, y);
          for (int x = x_first; x < x_last; ++x, pixel += 4) outside.store(pixel);
          continue;
        }
        // Else the pixels whose three positions lie clear of the edges run without checks: the
        // positions being linear in the column fraction, those clear by twice the margin have
        // fractions in one interval, found from the lines (the checks' margin leaves room for its
        // rounding).
        double f_low = -std::numeric_limits<double>::infinity(), f_high = std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < 3; ++c) {
          clear_fractions(line[c].edge_x, line[c].step_x, 2.0 * kMarginPx, scene.width_px - 1.0 - 2.0 * kMarginPx, f_low, f_high);
          clear_fractions(line[c].edge_y, line[c].step_y, 2.0 * kMarginPx, scene.height_px - 1.0 - 2.0 * kMarginPx, f_low, f_high);
        }
        int clear_first = x_first, clear_last = x_first;
        if (f_low <= f_high) {
          const auto begin = fraction.begin();
          clear_first = static_cast<int>(std::lower_bound(begin + x_first, begin + x_last, f_low) - begin);
          clear_last = static_cast<int>(std::upper_bound(begin + clear_first, begin + x_last, f_high) - begin);
        }
        // The others pixel by pixel: the runs of pixels whose three positions are clear, the rest
        // checked (a position may look past the scene's edge).
        const auto clear_run = [&](int run_first, int run_last) {
          if (run_first < run_last)
            warp_clear_span(scene.rgba.data(), scene.width_px, scene.height_px, line, fraction.data(), run_first, run_last,
                            out.pixel(0, y), options.vector_isa);
        };
        const auto pixel_by_pixel = [&](int from, int to) {
          int run_first = from;
          for (int x = from; x < to; ++x) {
            const double f = fraction[static_cast<std::size_t>(x)];
            glm::dvec2 at[3];
            bool clear = true;
            for (std::size_t c = 0; c < 3; ++c) {
              at[c] = glm::dvec2(line[c].edge_x + f * line[c].step_x, line[c].edge_y + f * line[c].step_y);
              clear = clear && sampler.clear_of_edges(at[c], kMarginPx);
            }
            if (clear) continue;
            clear_run(run_first, x);
            run_first = x + 1;
            Float4 seen[3];
            for (std::size_t c = 0; c < 3; ++c) seen[c] = sampler.inside(at[c]) ? sampler.at(at[c]) : outside;
            // R from the red position, B from the blue, G and alpha from the green.
            select(red, seen[0], select(blue, seen[2], seen[1])).store(out.pixel(x, y));
          }
          clear_run(run_first, to);
        };
        pixel_by_pixel(x_first, clear_first);
        clear_run(clear_first, clear_last);
        pixel_by_pixel(clear_last, x_last);
      }
    }
  });
}

ImageRGBA warp_through_spectacles_reference(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                                            const SpectacleWarpOptions& options) {
  const std::vector<GridInterpolation> grids = channel_grids(scene, lens, frame, options);
  ImageRGBA out(frame.width_px, frame.height_px, 0.0f);
  // The three grids share their vertices' pixels: each column's cell is found once per frame, each
  // row's once per row, and the green position serves alpha too.
  std::vector<GridInterpolation::Row> columns(static_cast<std::size_t>(frame.width_px));
  for (int x = 0; x < frame.width_px; ++x) columns[static_cast<std::size_t>(x)] = grids[0].column(x);
  parallel_chunks(frame.height_px, options.threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const GridInterpolation::Row row = grids[0].row(y);
      for (int x = 0; x < frame.width_px; ++x) {
        float* pixel = out.pixel(x, y);
        const GridInterpolation::Row& column = columns[static_cast<std::size_t>(x)];
        const glm::dvec2 green = grids[1].at(row, column);
        pixel[0] = sample_bilinear(scene, grids[0].at(row, column), 0, options.outside_cd_m2[0]);
        pixel[1] = sample_bilinear(scene, green, 1, options.outside_cd_m2[1]);
        pixel[2] = sample_bilinear(scene, grids[2].at(row, column), 2, options.outside_cd_m2[2]);
        pixel[3] = sample_bilinear(scene, green, 3, 1.0f);
      }
    }
  });
  return out;
}

}  // namespace glarelab
