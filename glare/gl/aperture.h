#pragma once
// The GPU aperture rasteriser: draws an ApertureGeometry (glare/eye/aperture_geometry.h) into an R32F
// texture of N x N transmittances at s x s supersampling (glare/shaders/aperture_supersample.comp,
// then aperture_downsample.comp). The grid has pixel size dx = width / N with the optical axis at
// the centre of pixel (N/2, N/2), x right, y up, texel row 0 the top row (image order), exactly as
// the CPU rasteriser (glare/eye/aperture_raster.h). Coverage rule
// (the CPU rasteriser's): a subsample belongs to a primitive when its centre is inside it.
// Requires a current OpenGL 4.5 context; not thread-safe.
#include <cstdint>
#include <vector>

#include "glare/eye/aperture_geometry.h"
#include "core/gl/gl_objects.h"

namespace glarelab::gl {

class GlAperture {
 public:
  // Throws std::invalid_argument("GL aperture: ...") for size_px outside 16..4096, a width that is
  // not positive and finite, supersampling outside 2..8, or a supersampled grid beyond the GL limit.
  GlAperture(int size_px, double aperture_width_mm, int supersampling = 2);

  void draw(const ApertureGeometry& geometry);

  int size_px() const { return size_px_; }
  int supersampling() const { return supersampling_; }
  double aperture_width_mm() const { return aperture_width_mm_; }
  double pixel_size_mm() const { return aperture_width_mm_ / size_px_; }

  GLuint texture() const { return aperture_.get(); }                 // N x N, R32F
  GLuint supersampled_texture() const { return samples_.get(); }     // sN x sN, R32F
  std::vector<float> read() const;               // N * N, row 0 at the top
  std::vector<float> read_supersampled() const;  // (sN)^2, row 0 at the top

 private:
  int size_px_;
  double aperture_width_mm_;
  int supersampling_;
  Program draw_program_;
  Program downsample_program_;
  Texture samples_;
  Texture aperture_;
  Buffer discs_, lines_, polygons_, vertices_, bin_offsets_, bin_items_;
};

// Culling bins for aperture_supersample.comp: B x B bins over the supersampled grid of
// samples_across (S) samples, B = min(64, S); a disc or line is listed in every bin its bounding
// box (grown by one sample) touches, discs first, then lines (index | 0x80000000), each in index
// order. Returns the B*B + 1 offsets followed by the items.
int bins_across_for(int samples_across);
std::vector<std::uint32_t> bin_primitives(const ApertureGeometry& geometry, int samples_across, double aperture_width_mm,
                                          int supersampling);
// The optical axis in sample units, c = (S + s) / 2: the centre of pixel (N/2, N/2), where the CPU
// rasteriser puts it (glare/eye/aperture_raster.h); a sample (a, b) lies at ((a + 0.5 - c) h, (c - b - 0.5) h).
double axis_samples(int samples_across, int supersampling);

// Reads an R32F texture (row 0 = texel row 0).
std::vector<float> read_r32f(GLuint texture, int width, int height);

}  // namespace glarelab::gl
