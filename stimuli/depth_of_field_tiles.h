#pragma once
// The depth-of-field stage's layers (stimuli/depth_of_field.h) composited a tile of frame rows at a
// time: for each tile, every layer near to far is filled on the rows the tile's outputs gather
// (its rows and the kernel's reach above and below), blurred on the tile's rows, added into the
// frame's sum through the nearer layers' transmission, and the tile's rows are divided by their
// coverage at the end.
//
// Why tiles. Done a layer at a time over the whole frame, each covered pixel was read from the
// image and written to the layer's rows, then its sum read and written, once a layer (2.7 layers a
// pixel on the whole-frame bench, blending included), each time from memory: the frame (33 MB at
// 1920 x 1080) does not stay in any cache between two layers. A tile's image rows, sums and
// transmission stay in the cache from its first layer to its last, so memory sees each pixel about
// once; the rows a layer's kernel reaches beyond the tile are filled again by the neighbouring tile
// (from the cache), and the blur itself is not repeated.
//
// The same bits. Every output pixel gets the same operations in the same order as a layer at a
// time would give it: the direct sum's value does not depend on which rows its call holds
// (depth_of_field_rows.h), the layers are added near to far, and the occluders are applied to the
// transmission at the same layers in the same order (a tile keeps the whole frame's rule: an
// occluder is applied before the first farther layer it hides, even where that layer has no pixel
// in the tile). So the result does not depend on the tile height nor on the thread count.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/vector_isa.h"
#include "stimuli/depth_layers.h"
#include "stimuli/depth_of_field_rows.h"
#include "stimuli/elliptical_kernel.h"

namespace glarelab {

// Frame rows a tile holds: at 1920 px its image rows and sums take 2 MB, which stay in the cache
// from the tile's first layer to its last; tiles of 16 to 64 rows took the same time within 1 ms on
// the whole-frame bench's input (docs/PERFORMANCE.md).
inline constexpr int kDepthOfFieldTileRows = 32;

// A rectangle of frame pixels, its corners inclusive (x1 < 0: empty).
struct FrameRectangle {
  int x0 = 0, y0 = 0;
  int x1 = -1, y1 = -1;
};

// A layer's blurred rows computed whole before the tiles (by FFT), kept for them: row r is frame row
// y0_px + r, its pixels [spans[r].first, spans[r].last) at frame column x0_px + first.
struct BlurredLayerRows {
  int x0_px = 0, y0_px = 0;
  std::vector<RowSpan> spans;
  std::vector<std::size_t> offsets;  // each row's first float in rgba
  std::vector<float> rgba;
};

// A layer of the plan as the tiles composite it.
struct TiledLayer {
  double vergence_dioptres = 0.0;
  const EllipticalKernel* kernel = nullptr;
  FrameRectangle box;                          // its pixels' bounding rectangle
  bool occludes = false;                       // whether it hides some farther layer
  double hides_up_to_vergence_dioptres = 0.0;  // it hides the layers below this vergence
  const DirectSumKernel* direct = nullptr;     // blurred directly in each tile with these taps,
  const BlurredLayerRows* blurred = nullptr;   // or blurred beforehand (one of the two is set)
};

// A tile's occluder: a blurred layer's coverage on the tile's rows, kept until the first layer far
// enough behind it to be hidden by it.
struct TileOccluder {
  double hides_up_to_vergence_dioptres = 0.0;
  std::vector<RowSpan> spans;        // a tile row's frame columns (empty: none)
  std::vector<std::size_t> offsets;  // where a tile row's frame column 0 lies in coverage
  std::vector<float> coverage;
};

// A thread's buffers, kept from tile to tile and from frame to frame.
struct DepthOfFieldTileBuffers {
  LayerRows rows;
  std::vector<float> transmission;  // the tile's rows, stored once some layer hides part of a row
  std::vector<char> hidden;         // tile rows whose transmission is stored
  std::vector<TileOccluder> pending;
  std::vector<std::vector<float>> coverages;  // the occluders' memory, returned when used
};

// What the tiles read and write: the image, the plan's runs, the layers (in the plan's order, far
// to near), the frame's sum (`result`, its rows' stored stretches in `written`).
struct TiledFrame {
  const ImageRGBA& image;
  const std::vector<std::vector<PixelRun>>& runs;
  const std::vector<TiledLayer>& layers;
  VectorIsa isa;
  ImageRGBA& result;
  std::vector<RowSpan>& written;
};

// Composites the frame rows [y_first, y_last) into frame.result: the layers' sum there divided by
// its coverage, alpha the image's. Touches only those rows of result and written. Returns whether
// every image pixel read was in range (R, G and B in [0, FLT_MAX]).
bool composite_tile(const TiledFrame& frame, int y_first, int y_last, DepthOfFieldTileBuffers& work);

// Layer `index`'s pixels as premultiplied RGBA on the frame rows [first_row, last_row] (inclusive)
// of `box`, laid out in `rows` for `kernel`: on its own pixels colour and coverage times 1 - their
// blend weight, on the pixels blended into it times their blend weight (in AVX-512 registers where
// `isa` is AVX-512: the same bits). Returns whether every pixel read was in range.
bool fill_layer_rows(const ImageRGBA& image, const std::vector<std::vector<PixelRun>>& runs, std::uint32_t index,
                     const FrameRectangle& box, int first_row, int last_row, const EllipticalKernel& kernel,
                     LayerRows& rows, int threads, VectorIsa isa);

}  // namespace glarelab
