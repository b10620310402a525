#version 450 core
// Display encoding through a measured calibration table (encoding = "table",
// core/display_calibration.h, docs/DISPLAY_CALIBRATION.md): stimulus luminance (cd/m2, linear
// Rec.709) -> each channel's wanted gain over black, x_c = clamp((L_c - black) / (peak - black),
// 0, 1) * full gain_c -> the drive at which the measured gain is x_c, interpolated linearly in
// luminance between the two measured points around it (DisplayCalibration::drive_for_gain).
// With uDitherLevels > 0 (8 bits: 255) the same 4x4 Bayer ordered dither as encode_display.frag,
// in gain: the mean gain over a 4x4 cell reproduces x_c to 1/16 of a code step.
layout(binding = 0) uniform sampler2D uStimulus;
// Row i of the table: (drive_i, gain_r, gain_g, gain_b), gains in cd/m2 above each channel's
// drive-0 reading; drive strictly increasing from 0 to 1, gains non-decreasing from 0.
layout(binding = 1) uniform sampler2D uTable;
// With dithering: texel k = the gains at drive k / uDitherLevels (the table read forward).
layout(binding = 2) uniform sampler2D uCodeGains;
uniform int uTableRows;
uniform float uBlack;          // cd/m2 at drive (0, 0, 0)
uniform float uPeakLuminance;  // cd/m2 at drive (1, 1, 1)
uniform int uDitherLevels;     // 0: no dithering; else the top code value of the target
out vec4 fragColor;

// 4x4 Bayer index matrix (Bayer 1973), thresholds (index + 0.5) / 16.
const float kBayer[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

vec4 row(int i) { return texelFetch(uTable, ivec2(i, 0), 0); }

// Drives of the three channels for gains x: a lower-bound search of all three channels at once
// over rows [1, rows - 1] (14 halvings cover the 16384 rows a texture holds), then linear
// interpolation in gain within the segment found. One loop of fixed length: a data-dependent
// loop per channel made llvmpipe's compiler spend minutes on the shader.
vec3 drive_for_gain(vec3 x) {
  ivec3 low = ivec3(1);
  ivec3 high = ivec3(uTableRows - 1);
  for (int step = 0; step < 15; ++step) {
    ivec3 middle = (low + high) / 2;
    vec3 at = vec3(row(middle.r).g, row(middle.g).b, row(middle.b).a);
    bvec3 searching = lessThan(low, high);
    bvec3 above = greaterThanEqual(at, x);
    high = mix(high, middle, bvec3(searching.x && above.x, searching.y && above.y, searching.z && above.z));
    low = mix(low, middle + 1, bvec3(searching.x && !above.x, searching.y && !above.y, searching.z && !above.z));
  }
  vec3 drive;
  for (int c = 0; c < 3; ++c) {
    vec4 r0 = row(high[c] - 1);
    vec4 r1 = row(high[c]);
    float g0 = r0[c + 1];
    float g1 = r1[c + 1];
    float t = g1 > g0 ? clamp((x[c] - g0) / (g1 - g0), 0.0, 1.0) : 1.0;
    drive[c] = x[c] <= 0.0 ? 0.0 : mix(r0.r, r1.r, t);
  }
  return drive;
}

float code_gain(float code, int channel) { return texelFetch(uCodeGains, ivec2(int(code), 0), 0)[channel + 1]; }

float dithered(float x, float drive, int channel, float threshold) {
  float levels = float(uDitherLevels);
  float code = min(floor(drive * levels), levels - 1.0);
  float x_low = code_gain(code, channel);
  float x_high = code_gain(code + 1.0, channel);
  // Guard the ends: float rounding of the drive may land a hair off the code that holds x.
  if (x < x_low && code > 0.0) {
    code -= 1.0;
    x_high = x_low;
    x_low = code_gain(code, channel);
  } else if (x > x_high && code < levels - 1.0) {
    code += 1.0;
    x_low = x_high;
    x_high = code_gain(code + 1.0, channel);
  }
  float fraction = x_high > x_low ? clamp((x - x_low) / (x_high - x_low), 0.0, 1.0) : 0.0;
  return (code + (fraction > threshold ? 1.0 : 0.0)) / levels;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 stimulus = texelFetch(uStimulus, pixel, 0).rgb;
  vec3 full_gain = row(uTableRows - 1).gba;
  vec3 x = clamp((stimulus - uBlack) / (uPeakLuminance - uBlack), 0.0, 1.0) * full_gain;
  vec3 drive = drive_for_gain(x);
  if (uDitherLevels > 0) {
    float threshold = (kBayer[(pixel.y & 3) * 4 + (pixel.x & 3)] + 0.5) / 16.0;
    drive = vec3(dithered(x.r, drive.r, 0, threshold), dithered(x.g, drive.g, 1, threshold),
                 dithered(x.b, drive.b, 2, threshold));
  }
  fragColor = vec4(drive, 1.0);
}
