#version 450 core
// Display encoding: stimulus luminance (cd/m2, linear Rec.709) -> relative drive in [0, 1] by the
// display's peak luminance, clipped (a display cannot exceed its white), then encoded with the
// sRGB transfer function (IEC 61966-2-1) or a pure power law 1/gamma.
layout(binding = 0) uniform sampler2D uStimulus;
uniform float uPeakLuminance;  // cd/m2 of display white
uniform int uEncoding;         // 0 = sRGB, 1 = gamma
uniform float uGamma;
out vec4 fragColor;

float encode_srgb(float linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

void main() {
  vec3 relative = clamp(texelFetch(uStimulus, ivec2(gl_FragCoord.xy), 0).rgb / uPeakLuminance, 0.0, 1.0);
  vec3 encoded = uEncoding == 0
      ? vec3(encode_srgb(relative.r), encode_srgb(relative.g), encode_srgb(relative.b))
      : pow(relative, vec3(1.0 / uGamma));
  fragColor = vec4(encoded, 1.0);
}
