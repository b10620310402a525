#version 450
// The image's R, G, B into two complex layers of the padded FFT grid, R + iG and B (zero beyond the
// image and in B's imaginary part; complex_multiply.comp separates R's and G's spectra), on the GPU
// so that only the image itself crosses the bus.
// Pixels brighter than the split threshold are left out: bright_splat.comp adds them directly
// (glare/gl/convolution.h, "Dynamic range").
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) writeonly buffer Padded { vec2 padded[]; };  // 2 layers, row-major
layout(std430, binding = 1) readonly buffer Image { vec4 image[]; };      // width x height RGBA
uniform int uWidth;
uniform int uHeight;
uniform int uPaddedWidth;
uniform int uPaddedHeight;
// max(R, G, B) above this: bright. The host rounds its double threshold down to the float below it,
// so this comparison picks exactly the pixels its own does; the largest float when nothing is split.
uniform float uBrightThreshold;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uPaddedWidth || p.y >= uPaddedHeight) return;
  vec3 rgb = vec3(0.0);
  if (p.x < uWidth && p.y < uHeight) {
    const vec4 value = image[p.y * uWidth + p.x];
    if (!(max(value.r, max(value.g, value.b)) > uBrightThreshold)) rgb = value.rgb;
  }
  const int layer = uPaddedWidth * uPaddedHeight;
  const int index = p.y * uPaddedWidth + p.x;
  padded[index] = rgb.rg;
  padded[layer + index] = vec2(rgb.b, 0.0);
}
