#version 450
// Pupil function for the FFT with a sphero-cylindrical power error E (glare/refraction/astigmatic_phase.h):
//   phi(x, y) = (pi / lambda) (E_xx x^2 + 2 E_xy x y + E_yy y^2).
// The x^2 and y^2 terms separate, as in psf_load_aperture.comp: exp(i pi E_xx x_i^2 / lambda) per
// column and exp(i pi E_yy y_j^2 / lambda) per row, computed on the CPU in double. The cross term
// exp(i 2 pi E_xy x y / lambda) does not separate and is made here, exactly reduced:
//   x_i y_j = (i - N/2)(N/2 - j) dx^2 = k dx^2, k an exact integer (|k| <= N^2 / 4,
// 2^22 at N = 4096),
// so the phase in turns is b k with b = E_xy dx^2 / lambda. The CPU hands frac(b) as a 64-bit
// fixed-point fraction (uCrossTurns: high word, low word; glare/gl/cross_phase_turns.h); |k| times
// it modulo 2^64 (32 x 64-bit multiply by umulExtended, wrapping) is frac(b |k|) to 2^-43 turns
// for every |k| <= 2^22 (the rounding of frac(b), 2^-65, times |k|). The top 12 bits pick
// exp(2 pi i m / 4096) from a table computed in double on the CPU; the rest, |delta| <= pi / 4096
// rad, is exp(i delta) = 1 - delta^2 / 2 + i (delta - delta^3 / 6) to 2e-14. No shader sin/cos:
// GLSL leaves their precision to the implementation (Vulkan, for comparison, allows sin/cos an
// absolute error of 2^-11 on [-pi, pi]); no fp64 either, although GL 4.0+ has it (llvmpipe too):
// it runs at 1/16 to 1/64 of the float rate on consumer GPUs, and the integers make it exact anyway.
// docs/GLARE_OPTICS.md ("The astigmatic cross term") gives the measured agreement.
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform readonly image2D uAperture;  // row 0 at the top
layout(std430, binding = 0) writeonly buffer Field { vec2 field[]; };
layout(std430, binding = 1) readonly buffer PhaseX { vec2 phase_x[]; };  // exp(i pi E_xx x_i^2 / lambda) per column
layout(std430, binding = 2) readonly buffer PhaseY { vec2 phase_y[]; };  // exp(i pi E_yy y_j^2 / lambda) per row
layout(std430, binding = 3) readonly buffer Turns { vec2 turns[]; };     // exp(2 pi i m / 4096), m = 0..4095
uniform int uSize;
uniform uvec2 uCrossTurns;  // frac(E_xy dx^2 / lambda) * 2^64: (bits 63..32, bits 31..0)

const uint kTableBits = 12u;
const uint kResidualBits = 32u - kTableBits;  // the bits of the high word below the table index
const float kTwoPi = 6.28318530717958648;
const float kTwoToMinus32 = 2.3283064365386962890625e-10;  // 2^-32, exact in float (GLSL has no hex floats)

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// exp(2 pi i frac(b) m) for m = |k|.
vec2 cross_factor(uint m) {
  uint carry, low;
  umulExtended(m, uCrossTurns.y, carry, low);  // m * low word = carry 2^32 + low
  const uint high = m * uCrossTurns.x + carry;  // bits 63..32 of m * frac(b) 2^64 mod 2^64 (wraps)
  // Nearest table entry (the rounding carry past 2^32 wraps to entry 0, which is right modulo a turn).
  const uint index = (high + (1u << (kResidualBits - 1u))) >> kResidualBits;
  // The rest, signed, in units of 2^-32 turns: high - index 2^20 modulo 2^32, |rest| <= 2^19.
  const int rest = int(high - (index << kResidualBits));
  const float delta = kTwoPi * ((float(rest) + float(low) * kTwoToMinus32) * kTwoToMinus32);
  const float delta2 = delta * delta;
  return complex_multiply(turns[index & ((1u << kTableBits) - 1u)],
                          vec2(1.0 - 0.5 * delta2, delta - delta * delta2 * (1.0 / 6.0)));
}

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= uSize || texel.y >= uSize) return;
  const float transmittance = imageLoad(uAperture, texel).r;
  const int k = (texel.x - uSize / 2) * (uSize / 2 - texel.y);
  vec2 cross = cross_factor(uint(abs(k)));
  if (k < 0) cross.y = -cross.y;  // exp(2 pi i b k) for k < 0 is the conjugate of that for |k|
  field[texel.y * uSize + texel.x] =
      transmittance * complex_multiply(complex_multiply(phase_x[texel.x], phase_y[texel.y]), cross);
}
