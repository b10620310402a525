#version 450
// Scotopic colour vision after tone mapping (Luidolt 2020, section 5.4;
// stimuli/perception/scotopic_colour.h), weighted by the rod sensitivity sigma(L_i) of Eq. 5.4 at
// the adapted luminance (from the host in double):
//   form 0, Eq. 5.18: SV = RGB (1 - sigma) + [1.05, 0.97, 1.27] L' sigma, L' of Eq. 5.1;
//   form 1, Spencer et al. 1995: HSV saturation reduced by r = 0.7 sigma, hue and value kept:
//           every channel V - (V - c) (1 - r), V the largest channel.
// Alpha kept. Float32: sums of products of positive terms, a few ulps.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };
uniform int uWidth;
uniform int uHeight;
uniform int uForm;           // 0 luidolt_tint, 1 spencer_desaturation
uniform float uRod;          // sigma(L_i), Eq. 5.4
uniform float uOneMinusRod;  // 1 - sigma(L_i)
uniform float uKeep;         // 1 - saturation reduction (Spencer)

const vec3 kTint = vec3(1.05, 0.97, 1.27);  // Eq. 5.18

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uWidth || p.y >= uHeight) return;
  const int i = p.y * uWidth + p.x;
  const vec4 c = source[i];
  vec3 shifted;
  if (uForm == 0) {
    const float luminance = 0.2125 * c.r + 0.7154 * c.g + 0.0721 * c.b;  // Eq. 5.1
    shifted = c.rgb * uOneMinusRod + kTint * (luminance * uRod);
  } else {
    const float value = max(c.r, max(c.g, c.b));
    shifted = value - (value - c.rgb) * uKeep;
  }
  target[i] = vec4(shifted, c.a);
}
