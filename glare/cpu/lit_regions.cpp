#include "glare/cpu/lit_regions.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "glare/cpu/fftw_float_plan.h"
#include "glare/parallel_rows.h"

namespace glarelab {
namespace {

constexpr int kTilePx = 8;

bool lit(const float* p) { return p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f; }

// Whether any of R, G, B of `count` pixels is not 0 (+0 or -0; NaN counts as lit, as in lit()):
// the bits without the sign, or-ed, so that the compiler vectorises the loop.
bool any_lit(const float* pixels, int count) {
  std::uint32_t bits = 0;
  for (int k = 0; k < 4 * count; ++k) {
    std::uint32_t word;
    std::memcpy(&word, pixels + k, sizeof word);
    bits |= (k % 4 == 3) ? 0u : (word & 0x7fffffffu);
  }
  return bits != 0;
}

// Occupancy of kTilePx x kTilePx tiles, tiles_x across.
struct Tiles {
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::uint8_t> lit;
  bool at(int tx, int ty) const { return lit[static_cast<std::size_t>(ty) * tiles_x + tx] != 0; }
};

struct TileBox {
  int x0, y0, x1, y1;  // tiles [x0, x1) x [y0, y1)
};

// The occupied part of `box`; x1 <= x0 when nothing in it is lit.
TileBox shrink(const Tiles& tiles, TileBox box) {
  TileBox tight{box.x1, box.y1, box.x0, box.y0};
  for (int ty = box.y0; ty < box.y1; ++ty)
    for (int tx = box.x0; tx < box.x1; ++tx)
      if (tiles.at(tx, ty)) {
        tight.x0 = std::min(tight.x0, tx), tight.x1 = std::max(tight.x1, tx + 1);
        tight.y0 = std::min(tight.y0, ty), tight.y1 = std::max(tight.y1, ty + 1);
      }
  return tight;
}

// The X-Y cut: the widest empty band of columns (then rows) of at least gap_tiles splits the box.
void cut(const Tiles& tiles, TileBox box, int gap_tiles, std::vector<TileBox>& out) {
  box = shrink(tiles, box);
  if (box.x1 <= box.x0) return;
  for (const bool columns : {true, false}) {
    const int first = columns ? box.x0 : box.y0, last = columns ? box.x1 : box.y1;
    int best_start = -1, best_length = 0, run_start = -1;
    for (int k = first; k <= last; ++k) {
      bool empty = k < last;
      for (int j = columns ? box.y0 : box.x0; empty && j < (columns ? box.y1 : box.x1); ++j)
        empty = !(columns ? tiles.at(k, j) : tiles.at(j, k));
      if (empty && run_start < 0) run_start = k;
      if (!empty && run_start >= 0) {
        if (k - run_start > best_length) best_start = run_start, best_length = k - run_start;
        run_start = -1;
      }
    }
    if (best_length >= gap_tiles) {  // a shrunk box starts and ends lit: the band is interior
      TileBox before = box, after = box;
      (columns ? before.x1 : before.y1) = best_start;
      (columns ? after.x0 : after.y0) = best_start + best_length;
      cut(tiles, before, gap_tiles, out);
      cut(tiles, after, gap_tiles, out);
      return;
    }
  }
  out.push_back(box);
}

// The tight pixel box of the lit pixels in a tile box (its edge tiles hold some).
PixelBox tighten(const ImageRGBA& image, const TileBox& box) {
  const int px0 = box.x0 * kTilePx, py0 = box.y0 * kTilePx;
  const int px1 = std::min(image.width_px, box.x1 * kTilePx), py1 = std::min(image.height_px, box.y1 * kTilePx);
  const auto row_lit = [&](int y) {
    for (int x = px0; x < px1; ++x)
      if (lit(image.pixel(x, y))) return true;
    return false;
  };
  const auto column_lit = [&](int x, int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      if (lit(image.pixel(x, y))) return true;
    return false;
  };
  int y0 = py0, y1 = py1, x0 = px0, x1 = px1;
  while (y0 < y1 && !row_lit(y0)) ++y0;
  while (y1 > y0 && !row_lit(y1 - 1)) --y1;
  while (x0 < x1 && !column_lit(x0, y0, y1)) ++x0;
  while (x1 > x0 && !column_lit(x1 - 1, y0, y1)) --x1;
  return PixelBox{x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

std::vector<PixelBox> lit_regions(const ImageRGBA& image, int gap_px, int max_boxes) {
  Tiles tiles;
  tiles.tiles_x = (image.width_px + kTilePx - 1) / kTilePx;
  tiles.tiles_y = (image.height_px + kTilePx - 1) / kTilePx;
  tiles.lit.assign(static_cast<std::size_t>(tiles.tiles_x) * tiles.tiles_y, 0);
  // Tile rows on threads: each writes only its own tiles.
  parallel_chunks(tiles.tiles_y, kGlareCpuThreads, [&](int first, int last) {
    for (int ty = first; ty < last; ++ty)
      for (int y = ty * kTilePx; y < std::min(image.height_px, (ty + 1) * kTilePx); ++y) {
        const float* row = image.pixel(0, y);
        std::uint8_t* marks = &tiles.lit[static_cast<std::size_t>(ty) * tiles.tiles_x];
        for (int tx = 0; tx < tiles.tiles_x; ++tx) {
          if (marks[tx] != 0) continue;  // already lit by an earlier row of the tile
          const int x0 = tx * kTilePx;
          if (any_lit(row + 4 * x0, std::min(kTilePx, image.width_px - x0))) marks[tx] = 1;
        }
      }
  });
  std::vector<TileBox> boxes;
  // A band of k empty tiles holds at least k kTilePx empty pixels.
  const int gap_tiles = std::max(1, (gap_px + kTilePx - 1) / kTilePx);
  cut(tiles, TileBox{0, 0, tiles.tiles_x, tiles.tiles_y}, gap_tiles, boxes);
  if (boxes.empty()) return {};
  if (static_cast<int>(boxes.size()) > max_boxes) {
    TileBox all = boxes.front();
    for (const TileBox& box : boxes)
      all = TileBox{std::min(all.x0, box.x0), std::min(all.y0, box.y0), std::max(all.x1, box.x1), std::max(all.y1, box.y1)};
    boxes = {all};
  }
  std::vector<PixelBox> out;
  for (const TileBox& box : boxes) out.push_back(tighten(image, box));
  return out;
}

}  // namespace glarelab
