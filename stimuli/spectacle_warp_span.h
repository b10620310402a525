#pragma once
// The spectacle warp's inner loop (stimuli/spectacle_warp.h): the output pixels of one row that lie
// in one grid cell whose scene positions, for every channel, are clear of the scene's edges. Along
// a row the grid's bilinear interpolation is linear within a cell, so a channel's position at
// column fraction f is edge + f * step; the scene is sampled bilinearly there in float (R from the
// red position, B from the blue, G and alpha from the green) with no edge checks.
//
// Three forms, the same contract (within 1e-5 of the float64 reference by stage_timing.h's pixel
// metric, and the same bits whatever the thread count; tests/stimuli_spectacle_warp_test.cpp runs
// each the CPU has); their last bits differ (not the same operations), each within the contract:
// - sse2: each channel's position as an (x, y) pair, its weights' fractions rounded to float,
//   1 - f taken in double first, and the sample wy0 (wx0 TL + wx1 TR) + wy1 (wx0 BL + wx1 BR) of
//   all four floats of each corner pixel, the three results' lanes then selected.
// - avx2_fma: the three channels' positions at once (four double lanes: R, G, B, G), each lane's
//   cell by a floor in double and its corner's offset as an integer-valued double (no conversion to
//   integers and back), the factors 1 - fx, fx, 1 - fy, fy each rounded once to float from double
//   (1 - f taken in double) and multiplied in float: (1 - fx, fx) (wy_top top + wy_bottom bottom).
//   A corner row's two pixels are one 256-bit load per channel, the lanes blended so each holds its
//   own channel's values (alpha the green position's), and the two halves added.
// - avx512: two pixels at once (eight double lanes), the cells as avx2_fma finds them, the four
//   corner weights as products in double each rounded once to float, the corners loaded as
//   avx2_fma loads them and each pixel's 16 products summed by quarters (an odd cell's last pixel
//   by the avx2_fma form).
// Every factor or weight keeps float's relative precision and every product is of non-negative
// terms, so a sample is within a few float roundings of its exact value however steep the scene's
// edges (a 1e7 : 1 edge keeps the same relative error). The wide forms find each pixel's (or
// pair's) cells and weights one step ahead of its loads, and ask for the scene rows two and three
// below into the cache a row ahead: the loop is bound by its loads' latency, not its arithmetic
// (docs/PERFORMANCE.md).
#include <cstddef>

#include "core/vector_isa.h"

namespace glarelab {

// One channel's scene position along a row cell: at column fraction f, (edge_x + f step_x,
// edge_y + f step_y) in scene pixels (pixel i's centre at i).
struct WarpCellLine {
  double edge_x = 0.0, edge_y = 0.0, step_x = 0.0, step_y = 0.0;
};

// Output pixels [first, last) of a row into out_row (RGBA floats), pixel x at column fraction
// fraction[x] of its cell. Every position met must lie in [0, width - 1) x [0, height - 1) of the
// scene (RGBA floats, width_px x height_px), the caller's check. `isa` must run on this CPU
// (core/vector_isa.h); avx2_fma and avx512 need 4 width height < 2^31 floats, else the sse2 form
// runs.
void warp_clear_span(const float* scene, int width_px, int height_px, const WarpCellLine line[3], const double* fraction,
                     int first, int last, float* out_row, VectorIsa isa);

// The same for cells [first_cell, last_cell) of a row in one call: cell i's pixels are
// [cell_first[i], cell_first[i + 1]), its three channels' lines lines[3 i], [3 i + 1], [3 i + 2].
void warp_clear_cells(const float* scene, int width_px, int height_px, const WarpCellLine* lines, const int* cell_first,
                      int first_cell, int last_cell, const double* fraction, float* out_row, VectorIsa isa);

}  // namespace glarelab
