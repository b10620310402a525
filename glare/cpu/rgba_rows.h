#pragma once
// One row of interleaved RGBA pixels to and from planes of R, G, B (and A), as the planned float
// convolution copies its scene in and its result out (glare/cpu/float_convolution.h). Four pixels a step
// in SSE registers (a 4 x 4 transpose) where the compiler has them, x86-64 always: the compiler
// made the element-by-element loops one scalar load, compare and store per value, and at N = 512
// the copy in took a third of the scene's transform. Copies and ordered comparisons only: the
// values and the verdict are the same bits as the scalar loops' (tests/glare_rgba_rows_test.cpp).

namespace glarelab {

// red[x], green[x], blue[x] (and alpha[x] unless alpha is null) = pixel x of `rgba`, x < width.
// Returns whether every R, G and B value is >= 0 and finite (alpha is not checked): NaN, infinities
// and negative values make it false, which the convolution turns into a refusal of the scene.
bool split_rgba_row(const float* rgba, int width, float* red, float* green, float* blue, float* alpha);

// Pixel x of `rgba` = (red[x], green[x], blue[x], alpha[x]), x < width.
void join_rgba_row(const float* red, const float* green, const float* blue, const float* alpha, int width, float* rgba);

}  // namespace glarelab
