#version 450
// Luidolt 2020, section 5.1, step 3: one level of the Gaussian pyramid (Burt and Adelson's
// [1 4 6 4 1] / 16 in x and y, edges clamped, every second sample kept) on the (w Y, w) cells,
// uSize x uSize -> uSize / 2 x uSize / 2. The 5 x 5 product kernel equals the reference's row pass
// then column pass (frame_adaptation_luminance.cpp, pyramid_reduce).
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Source { vec2 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec2 target[]; };
uniform int uSize;  // of the source level

const float kBinomial[5] = float[5](1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0);

void main() {
  const int half_size = uSize / 2;
  const ivec2 out_cell = ivec2(gl_GlobalInvocationID.xy);
  if (out_cell.x >= half_size || out_cell.y >= half_size) return;
  vec2 sum = vec2(0.0);
  for (int ky = -2; ky <= 2; ++ky) {
    const int sy = clamp(2 * out_cell.y + ky, 0, uSize - 1);
    vec2 row = vec2(0.0);
    for (int kx = -2; kx <= 2; ++kx) row += kBinomial[kx + 2] * source[sy * uSize + clamp(2 * out_cell.x + kx, 0, uSize - 1)];
    sum += kBinomial[ky + 2] * row;
  }
  target[out_cell.y * half_size + out_cell.x] = sum;
}
