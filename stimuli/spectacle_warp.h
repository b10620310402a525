#pragma once
// A frame as seen through a spectacle lens (glare/refraction/spectacle_lens.h; docs/SPECTACLES.md): each
// output pixel is the visual direction the eye turns to, and shows the scene where the lens sends
// that line of sight. Per colour channel at its own wavelength, so the lens' transverse chromatic
// aberration follows from its Abbe number.
//
// The frame's geometry: a flat (rectilinear) frame with the primary line of sight through its
// centre, x to the observer's right, row 0 at the top; the pixel offset (u, v) from the centre
// (v up) is the direction (u k, v k, 1) from the eye's centre of rotation, k = 2 tan(dpp / 2) with
// dpp the degrees per pixel at the centre (stimuli/display_model.h: pitch / distance). The scene
// lies in the same frame: distant by default (an object direction is looked up directly), or a flat
// frame `scene_distance_mm` in front of the cornea, where the ray leaving the lens is intersected
// with that plane and the point looked up by its direction from the centre of rotation. The
// difference is the ray's sideways offset at the lens, about h |tan a - tan a'| (0.6 mm for a +4 D
// lens at 10 deg, h the lens' distance from the centre of rotation), 1 mrad at 600 mm.
//
// Interpolation: the mapping is traced at the vertices of a grid spanning the frame's pixel centres
// (grid_vertices per side) and interpolated bilinearly in between; the scene is resampled
// bilinearly (continuous pixel coordinates, pixel i's centre at i), and seen as `outside_cd_m2`
// where the lens looks past the scene's edge.
#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/image.h"
#include "core/vector_isa.h"
#include "glare/refraction/spectacle_lens.h"

namespace glarelab {

struct SpectacleFrame {
  int width_px = 0;
  int height_px = 0;
  double degrees_per_pixel_at_centre = 0.0;

  // The visual direction (unit; from the centre of rotation) of the continuous pixel position.
  glm::dvec3 direction(glm::dvec2 pixel) const;
  // The continuous pixel position of a direction (z > 0).
  glm::dvec2 pixel(glm::dvec3 direction) const;
};

struct SpectacleWarpOptions {
  int grid_vertices = 33;
  // Wavelengths of the R, G, B channels: the Fraunhofer C, d and F lines, so the green channel sees
  // the lens at n_d (its prescribed power) and red against blue differs by n_F - n_C, the
  // dispersion the Abbe number measures.
  std::array<double, 3> wavelengths_nm{kFraunhoferC_nm, kFraunhoferD_nm, kFraunhoferF_nm};
  std::array<float, 3> outside_cd_m2{0.0f, 0.0f, 0.0f};
  std::optional<double> scene_distance_mm;  // unset: a distant scene
  int threads = 1;
  // The form of the per-pixel loop (stimuli/spectacle_warp_span.h: SSE2, AVX2 or AVX-512): the
  // widest this CPU runs, unless a test pins one; one this CPU does not run is refused.
  VectorIsa vector_isa = widest_vector_isa_with_avx512();
};

// For every output pixel, the continuous scene pixel position it shows (pixel i's centre at i).
struct SourceMap {
  int width_px = 0;
  int height_px = 0;
  std::vector<glm::dvec2> position_px;  // row-major, row 0 at the top
  const glm::dvec2& at(int x, int y) const { return position_px[static_cast<std::size_t>(y) * width_px + x]; }
};

// The mapping traced at the vertices alone: grid_vertices x grid_vertices scene positions, row-major,
// the vertices running from the first to the last pixel centre in each direction.
std::vector<glm::dvec2> trace_grid_vertices(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm,
                                            int grid_vertices, std::optional<double> scene_distance_mm = {});

// The mapping traced at grid_vertices x grid_vertices vertices and interpolated bilinearly.
// Throws std::invalid_argument ("stimuli/spectacle_warp: ...") when a vertex's line of sight misses
// the lens (a field of view the lens does not cover), for grid_vertices < 2, a frame without pixels
// a degrees_per_pixel_at_centre outside (0, 10] or a scene_distance_mm not beyond the lens.
SourceMap grid_source_map(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm, int grid_vertices,
                          std::optional<double> scene_distance_mm = {}, int threads = 1);
// The reference: every pixel's line of sight traced.
SourceMap traced_source_map(const SpectacleLens& lens, const SpectacleFrame& frame, double wavelength_nm,
                            std::optional<double> scene_distance_mm = {}, int threads = 1);

// The scene (linear RGB, cd/m2, the frame's size) as seen through the lens; alpha follows the green
// channel's mapping. Throws as grid_source_map does, and for a scene whose size is not the frame's
// or a wavelength outside 360-830 nm.
ImageRGBA warp_through_spectacles(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                                  const SpectacleWarpOptions& options = {});
// The same into `out` (not the scene), whose memory is reused when it has the frame's size: a
// session's frames then write into pages already mapped, as the streaming floor does (a fresh
// frame's page faults and zeroing are a cost of their own: docs/PERFORMANCE.md).
void warp_through_spectacles(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                             const SpectacleWarpOptions& options, ImageRGBA& out);
// The three channels' grids of one lens and frame, traced at the options' wavelengths, vertex count
// and scene distance: the part of a frame's warp that does not depend on the scene (3 x 33 x 33
// traced rays, about 2 ms of one thread's CPU at 1920 x 1080, docs/PERFORMANCE.md), kept by a caller
// whose lens and frame stay the same from frame to frame. Throws as grid_source_map does, and for a
// wavelength outside 360-830 nm.
class SpectacleWarpGrids {
 public:
  SpectacleWarpGrids(const SpectacleLens& lens, const SpectacleFrame& frame, const SpectacleWarpOptions& options);
  // True when these grids serve this frame with these options: the same frame (size and scale) and
  // the same wavelengths, vertex count and scene distance (the options' other fields are the warp's).
  bool traced_for(const SpectacleFrame& frame, const SpectacleWarpOptions& options) const;
  const SpectacleFrame& frame() const { return frame_; }
  int grid_vertices() const { return grid_vertices_; }
  // Channel c's (R, G, B) vertices, row-major as trace_grid_vertices gives them.
  const std::vector<glm::dvec2>& vertices(int channel) const { return vertices_[static_cast<std::size_t>(channel)]; }

 private:
  SpectacleFrame frame_;
  int grid_vertices_;
  std::array<double, 3> wavelengths_nm_;
  std::optional<double> scene_distance_mm_;
  std::array<std::vector<glm::dvec2>, 3> vertices_;
};

// The grids of one lens, traced when first asked for and again only when the frame or the tracing
// options change; shared by the threads of a session (a lock around the look-up).
class SpectacleWarpGridCache {
 public:
  explicit SpectacleWarpGridCache(std::shared_ptr<const SpectacleLens> lens);
  const SpectacleLens& lens() const { return *lens_; }
  std::shared_ptr<const SpectacleWarpGrids> grids(const SpectacleFrame& frame, const SpectacleWarpOptions& options);

 private:
  std::shared_ptr<const SpectacleLens> lens_;
  std::mutex mutex_;
  std::shared_ptr<const SpectacleWarpGrids> grids_;
};

// The warp through grids already traced: the same frame as warp_through_spectacles with the lens
// they were traced for. Throws as warp_through_spectacles does, and when the grids were not traced
// for the options' wavelengths, vertex count and scene distance.
void warp_through_spectacles(const ImageRGBA& scene, const SpectacleWarpGrids& grids, const SpectacleWarpOptions& options,
                             ImageRGBA& out);
ImageRGBA warp_through_spectacles(const ImageRGBA& scene, const SpectacleWarpGrids& grids, const SpectacleWarpOptions& options);

// Its float64 reference: each pixel's position by the grid's bilinear formula and each sample in
// double. warp_through_spectacles takes the positions along each row cell by cell (linear there)
// and the samples in float, within 1e-5 of this by stage_timing.h's pixel metric
// (tests/stimuli_spectacle_warp_test.cpp); the bench prints the error beside its time.
ImageRGBA warp_through_spectacles_reference(const ImageRGBA& scene, const SpectacleLens& lens, const SpectacleFrame& frame,
                                            const SpectacleWarpOptions& options = {});

}  // namespace glarelab
