#version 450
// Pupil function for the FFT: aperture transmittance times the defocus phase exp(i phi),
// phi(x, y) = pi D (x^2 + y^2) / lambda (thin-lens focus error; glare/eye/aperture_geometry.h).
// The phase separates, exp(i a (x^2 + y^2)) = exp(i a x^2) exp(i a y^2), so the CPU evaluates it
// in double precision once per column and once per row and the shader only multiplies.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform readonly image2D uAperture;  // row 0 at the top
layout(std430, binding = 0) writeonly buffer Field { vec2 field[]; };
layout(std430, binding = 1) readonly buffer PhaseX { vec2 phase_x[]; };  // exp(i a x_i^2) per column
layout(std430, binding = 2) readonly buffer PhaseY { vec2 phase_y[]; };  // exp(i a y_j^2) per row
uniform int uSize;

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= uSize || texel.y >= uSize) return;
  const float transmittance = imageLoad(uAperture, texel).r;
  field[texel.y * uSize + texel.x] = transmittance * complex_multiply(phase_x[texel.x], phase_y[texel.y]);
}
