#pragma once
// A glared frame as a session keeps it between computing and showing it: the rectangle where it
// differs from the composed frame (the rest is the composed frame itself), in one of two
// precisions. Glare on a stimulus on a dark background changes the stimulus and the PSF's reach
// around it; a stimulus filling the display changes it all, and a trial prepares up to one frame
// per stimulus frame (30 whole 1920 x 1080 float32 RGBA frames are 1.0 GB).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/image.h"
#include "core/pixel_rect.h"
#include "stimuli/perception/gl_frame_buffer.h"

namespace glarelab {

enum class RegionPrecision {
  // float32 RGBA, bit for bit the glared frame: an interval's frame 0, the one `run --save-frames`
  // writes and `glarelab render` shows (linear cd/m2, a record of what was seen).
  exact,
  // binary16 R, G, B (core/half_float.h; alpha is 1 on upload, and nothing shown reads it): the
  // other frames, which only reach the display encoder. Half's relative step (<= 4.9e-4, 2^-24
  // cd/m2 absolute below 6.1e-5) is a fraction of a display code: the encoded code of a pixel stays
  // the same or moves by one at 8 and 10 bits with or without dithering
  // (tests/glared_region_test.cpp). 6 bytes a pixel against 16.
  half_rgb,
};

struct GlaredRegion {
  GlaredRegion() = default;
  GlaredRegion(const GlaredRegion&) = default;
  GlaredRegion(GlaredRegion&&) noexcept = default;
  GlaredRegion& operator=(const GlaredRegion&) = default;
  GlaredRegion& operator=(GlaredRegion&&) noexcept = default;
  // Hands `half_rgb`'s storage back for the next region changed_region() keeps (glared_region.cpp).
  ~GlaredRegion();

  int x0_px = 0, y0_px = 0;  // top left, row 0 at the top
  int width_px = 0, height_px = 0;
  // Rows bottom-up (OpenGL's order), so a region uploads as it is, with no copy per flip
  // (stimuli/frame_renderer.h); one of the two is filled, as `precision` asked.
  std::vector<float> exact_rgba;        // RegionPrecision::exact: 4 x width x height floats
  std::vector<std::uint16_t> half_rgb;  // RegionPrecision::half_rgb: 3 x width x height halves
  // Or the frame left on the GPU by the GL frame engine (stimuli/frame_engine.h), kept there until
  // it is drawn: each eye's part in a GL buffer of the display's context (RGBA32F, row 0 at the
  // top), drawn into its view; the rectangle is the views' bounding box, nothing is on the host.
  struct GpuPart {
    std::shared_ptr<const gl::GlFrameBuffer> frame;
    PixelRect view;
  };
  std::vector<GpuPart> gpu_parts;
  // Unique to each region changed_region() makes (core/image_token.h, never 0; a copy keeps it): a flip of the region
  // the stimulus framebuffer already holds only re-encodes it (SessionLoop::draw), as for static
  // glare, whose interval shows one region at every flip.
  std::uint64_t serial = 0;
  // Where its halves differ from those of the region with serial `previous_serial` (the
  // interval's frame before it, of the same rectangle; frame coordinates, 0 x 0 when nothing
  // differs): a flip that follows that region's flip writes and encodes only this rectangle
  // (SessionLoop::draw). Against an exact frame 0, its values are compared as the halves they round
  // to: outside the rectangle the framebuffer keeps frame 0's float32 values, which round to this
  // frame's halves, so each code shown there is within one of this frame's exact code, as a half
  // frame's codes are (RegionPrecision::half_rgb), and frame 1 is not drawn whole (in the demo, a
  // third of the frame instead of all of it). 0: not known (frame 0, a region of another rectangle).
  std::uint64_t previous_serial = 0;
  PixelRect changed_since_previous;

  bool empty() const { return width_px == 0 || height_px == 0; }  // the glared frame equals the composed one
  std::size_t bytes() const { return exact_rgba.size() * sizeof(float) + half_rgb.size() * sizeof(std::uint16_t); }
};

// The rectangle of `glared` that differs from `composed` (same size, compared bit for bit over
// R, G, B and A), kept at `precision`. `differs_within`, when given, is a box the two are known to
// be equal outside (the union of GlareFrameReport::changed_boxes): only its pixels are compared,
// which finds the same rectangle without reading the rest of two whole frames (a small stimulus
// on a 1920 x 1080 display changes a small part of it). A box reaching past the frame is clipped.
GlaredRegion changed_region(const ImageRGBA& composed, const ImageRGBA& glared, RegionPrecision precision,
                            const std::optional<PixelRect>& differs_within = std::nullopt);

// Sets `region`'s previous_serial and changed_since_previous against `previous` when `region` is a
// half-precision region and `previous` one of the same rectangle, at half precision or exact: the
// bounding box of the pixels whose halves differ (compared bit for bit; an exact frame's values as
// the halves they round to). Otherwise leaves them unset. In the demo a dynamic frame differs from the
// one before it only on the dynamic lamp's side, about a third of the frame.
void mark_changes_since(GlaredRegion& region, const GlaredRegion& previous);

// Fills the storage that half precision regions take from (and hand back when freed) up to its
// bound with storages of `values` halves: a session whose intervals make a frame per flip does it
// before its first trial, so that its first such interval's frames neither allocate nor zero
// theirs (in the demo, a quarter of the worker's time for its first dynamic trial).
void fill_half_storage(std::size_t values);

// A frame kept on the GPU as the eyes' parts (each part's buffer the size of its view).
GlaredRegion gpu_region(std::vector<GlaredRegion::GpuPart> parts);

// The linear cd/m2 a region holds (float32 RGBA, row 0 at the top; a half region's alpha is 1).
ImageRGBA region_pixels(const GlaredRegion& region);

// Bytes of the frames of a trial's interval kept as changed regions, at most: frame 0 exact and the
// other frames at half precision, each at most the whole `width_px` x `height_px` frame.
std::size_t prepared_frames_bound_bytes(int width_px, int height_px, int frames);

}  // namespace glarelab
