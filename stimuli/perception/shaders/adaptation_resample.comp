#version 450
// Luidolt 2020, section 5.1, steps 1 and 2 (stimuli/perception/frame_adaptation_luminance.h): each
// pixel's luminance (Eq. 5.1) times the gaze Gaussian, and the Gaussian alone, resampled to
// uSize x uSize cells by exact area overlap. One invocation per cell; cells[] holds (w Y, w).
//
// Float32: the weight is exp(-(d^2 - d0^2) / (2 sigma^2)) with d0 the distance from the gaze to the
// nearest pixel centre, so the largest weight is exactly 1 and no weight underflows where the
// double reference's do not (the common factor exp(-d0^2 / (2 sigma^2)) cancels in
// mean(w Y) / mean(w)). d^2 - d0^2 is formed as (i/W) (i/W + 2 e) per axis, i the integer pixel
// offset from the nearest pixel and e that pixel's offset from the gaze (in frame widths, from the
// host in double), which has no cancellation. Overlaps are integers in units of 1 / uSize of a
// pixel, so the area weights are exact up to one division.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { vec4 frame[]; };
layout(std430, binding = 1) writeonly buffer Cells { vec2 cells[]; };
uniform int uWidth;
uniform int uHeight;
uniform int uSize;
uniform ivec2 uNearest;        // the pixel whose centre is nearest the gaze
uniform vec2 uNearestOffset;   // its centre minus the gaze, in frame widths (y scaled by H / W)
uniform float uInvTwoSigma2;   // 1 / (2 sigma^2), sigma in frame widths; 0: uniform weights

// Eq. 5.1 (Poynton's rounding of the Rec.709 weights).
float luidolt_luminance(vec3 rgb) { return 0.2125 * rgb.r + 0.7154 * rgb.g + 0.0721 * rgb.b; }

void main() {
  const ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  if (cell.x >= uSize || cell.y >= uSize) return;
  // Cell o spans [o n_in, (o + 1) n_in) and pixel i spans [i n_out, (i + 1) n_out), in units of
  // 1 / n_out of a pixel; weight = overlap / n_in (frame_adaptation_luminance.cpp, area_taps).
  const int x_begin = cell.x * uWidth, x_end = (cell.x + 1) * uWidth;
  const int y_begin = cell.y * uHeight, y_end = (cell.y + 1) * uHeight;
  const int x_first = x_begin / uSize, x_last = min(uWidth - 1, (x_end + uSize - 1) / uSize - 1);
  const int y_first = y_begin / uSize, y_last = min(uHeight - 1, (y_end + uSize - 1) / uSize - 1);
  const float inv_width = 1.0 / float(uWidth);
  vec2 sum = vec2(0.0);
  for (int y = y_first; y <= y_last; ++y) {
    const int y_overlap = min(y_end, (y + 1) * uSize) - max(y_begin, y * uSize);
    if (y_overlap <= 0) continue;
    const float dy = float(y - uNearest.y) * inv_width;
    const float ey = dy * (dy + 2.0 * uNearestOffset.y);
    vec2 row = vec2(0.0);
    for (int x = x_first; x <= x_last; ++x) {
      const int x_overlap = min(x_end, (x + 1) * uSize) - max(x_begin, x * uSize);
      if (x_overlap <= 0) continue;
      const float dx = float(x - uNearest.x) * inv_width;
      const float w = exp(-(dx * (dx + 2.0 * uNearestOffset.x) + ey) * uInvTwoSigma2);
      const float luminance = luidolt_luminance(frame[y * uWidth + x].rgb);
      row += float(x_overlap) * vec2(w * luminance, w);
    }
    sum += float(y_overlap) * row;
  }
  cells[cell.y * uSize + cell.x] = sum / (float(uWidth) * float(uHeight));
}
