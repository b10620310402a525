#version 450 core
// Display encoding (docs/DISPLAY_CALIBRATION.md): stimulus luminance (cd/m2, linear Rec.709) ->
// drive value in [0, 1], as stimuli/display_model.cpp DisplayModel::encode_rgb computes it in
// double. Each encoding maps the stimulus into its own linear domain x, clipped to what the
// display can show, and then encodes x:
//   0 sRGB   x = L / peak in [0, 1], IEC 61966-2-1 transfer function
//   1 gamma  x = L / peak in [0, 1], x^(1/gamma)
//   2 PQ     x = L / 10000 with L in [0, peak] (after Rec.709 -> BT.2020, ITU-R BT.2087, when
//            asked), SMPTE ST 2084 inverse EOTF
// (The measured table, encoding = "table", has its own pass: encode_display_table.frag.)
// With uDitherLevels > 0 (an 8-bit target: 255) the drive is quantised here with a 4x4 Bayer
// ordered dither in the linear domain: between the two code values around the drive, the upper
// is taken where the fraction of the way (in x, not in drive) exceeds the pixel's threshold, so
// the mean over a 4x4 cell reproduces x to 1/16 of a code step.
//
// ENCODING (0 sRGB, 1 gamma, 2 PQ) and DITHER (0, 1) are defined when the program is built
// (FrameRenderer builds one per pair in use): a software renderer (llvmpipe) runs both sides of a
// branch on a uniform, so a single program with every path in it paid for all of them, dithering
// included: 20 ms for a 1024 x 512 frame on 2 cores whatever the encoding.
#if !defined(ENCODING) || !defined(DITHER)
#error "encode_display.frag is built with ENCODING and DITHER defined"
#endif
layout(binding = 0) uniform sampler2D uStimulus;
uniform float uPeakLuminance;  // cd/m2 of display white
uniform float uGamma;
uniform int uBt2020;          // PQ: convert Rec.709 to BT.2020 primaries first
uniform int uDitherLevels;    // DITHER: the top code value of the target
out vec4 fragColor;

// SMPTE ST 2084:2014 constants (exact binary fractions).
const float kM1 = 2610.0 / 16384.0;
const float kM2 = 2523.0 / 4096.0 * 128.0;
const float kC1 = 3424.0 / 4096.0;
const float kC2 = 2413.0 / 4096.0 * 32.0;
const float kC3 = 2392.0 / 4096.0 * 32.0;

// ITU-R BT.2087-0, Eq. 2 (GLSL matrices are column-major: each vec3 is one column).
const mat3 kRec709ToBt2020 = mat3(vec3(0.6274, 0.0691, 0.0164), vec3(0.3293, 0.9195, 0.0880),
                                  vec3(0.0433, 0.0114, 0.8956));

// 4x4 Bayer index matrix (Bayer 1973), thresholds (index + 0.5) / 16.
const float kBayer[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

float encode(float x) {
#if ENCODING == 0
  return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
#elif ENCODING == 1
  return pow(x, 1.0 / uGamma);
#else
  float y_m1 = pow(x, kM1);
  return pow((kC1 + kC2 * y_m1) / (1.0 + kC3 * y_m1), kM2);
#endif
}

float decode(float v) {
#if ENCODING == 0
  return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
#elif ENCODING == 1
  return pow(v, uGamma);
#else
  float n_m2 = pow(v, 1.0 / kM2);
  return pow(max(n_m2 - kC1, 0.0) / (kC2 - kC3 * n_m2), 1.0 / kM1);
#endif
}

// The linear domain value x of each channel (see the header), clipped to what the display shows.
vec3 linear_domain(vec3 stimulus) {
#if ENCODING <= 1
  return clamp(stimulus / uPeakLuminance, 0.0, 1.0);
#else
  vec3 rgb = uBt2020 != 0 ? kRec709ToBt2020 * stimulus : stimulus;
  return clamp(rgb, 0.0, uPeakLuminance) / 10000.0;
#endif
}

float dithered(float x, float threshold) {
  float levels = float(uDitherLevels);
  float code = min(floor(encode(x) * levels), levels - 1.0);
  float x_low = decode(code / levels);
  float x_high = decode((code + 1.0) / levels);
  // Guard the ends: the encode of x may land a hair off the code that holds x.
  if (x < x_low && code > 0.0) {
    code -= 1.0;
    x_high = x_low;
    x_low = decode(code / levels);
  } else if (x > x_high && code < levels - 1.0) {
    code += 1.0;
    x_low = x_high;
    x_high = decode((code + 1.0) / levels);
  }
  float fraction = x_high > x_low ? clamp((x - x_low) / (x_high - x_low), 0.0, 1.0) : 0.0;
  return (code + (fraction > threshold ? 1.0 : 0.0)) / levels;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 x = linear_domain(texelFetch(uStimulus, pixel, 0).rgb);
#if DITHER
  float threshold = (kBayer[(pixel.y & 3) * 4 + (pixel.x & 3)] + 0.5) / 16.0;
  vec3 encoded = vec3(dithered(x.r, threshold), dithered(x.g, threshold), dithered(x.b, threshold));
#else
  vec3 encoded = vec3(encode(x.r), encode(x.g), encode(x.b));
#endif
  fragColor = vec4(encoded, 1.0);
}
