#version 450
// Tone mapping with the adapted luminance (Luidolt 2020, sections 3.4 and 6.1;
// stimuli/perception/tone_mapping.h): x = max(c, 0) * exposure, exposure = [0.6] 0.18 / L_a from
// the host in double, then Narkowicz's ACES fit per channel, or Hill's fit between the RRT and ODT
// colour matrices, clamped to [0, 1] and times the display peak; or each channel clipped to
// [0, peak]. Alpha kept. Constants as published (Narkowicz 2016; Hill, BakingLab ACES.hlsl, 2016).
// Float32: rational functions of x, a few ulps; Hill's numerator v (v + 0.0245786) - 0.000090537
// cancels near its root v = 0.0037, where the output is about 1e-9 of the peak.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Source { vec4 source[]; };
layout(std430, binding = 1) writeonly buffer Target { vec4 target[]; };
uniform int uWidth;
uniform int uHeight;
uniform int uCurve;       // 0 aces_narkowicz, 1 aces_hill, 2 none
uniform float uExposure;  // per cd/m2
uniform float uPeak;      // cd/m2

vec3 narkowicz(vec3 x) {
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 hill_fit(vec3 v) {
  const vec3 a = v * (v + 0.0245786) - 0.000090537;
  const vec3 b = v * (0.983729 * v + 0.4329510) + 0.238081;
  return a / b;
}

// Hill's ACESInputMat and ACESOutputMat, rows.
const vec3 kInput0 = vec3(0.59719, 0.35458, 0.04823);
const vec3 kInput1 = vec3(0.07600, 0.90834, 0.01566);
const vec3 kInput2 = vec3(0.02840, 0.13383, 0.83777);
const vec3 kOutput0 = vec3(1.60475, -0.53108, -0.07367);
const vec3 kOutput1 = vec3(-0.10208, 1.10813, -0.00605);
const vec3 kOutput2 = vec3(-0.00327, -0.07276, 1.07602);

vec3 hill(vec3 x) {
  const vec3 fitted = hill_fit(vec3(dot(kInput0, x), dot(kInput1, x), dot(kInput2, x)));
  return clamp(vec3(dot(kOutput0, fitted), dot(kOutput1, fitted), dot(kOutput2, fitted)), 0.0, 1.0);
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uWidth || p.y >= uHeight) return;
  const int i = p.y * uWidth + p.x;
  const vec4 c = source[i];
  vec3 mapped;
  if (uCurve == 2) {
    mapped = clamp(c.rgb, 0.0, uPeak);
  } else {
    // Negative channels would meet the curves' poles; they are black on a display anyway.
    const vec3 x = max(c.rgb, 0.0) * uExposure;
    mapped = uPeak * (uCurve == 1 ? hill(x) : narkowicz(x));
  }
  target[i] = vec4(mapped, c.a);
}
