#version 450
// The bright part of a split convolution, summed directly: every output pixel adds, for each bright
// pixel, its value times the PSF at their offset. Each term is exact to float rounding of itself,
// so a 1e8 cd/m2 source adds no FFT noise to a 1e-2 cd/m2 surround (linearity: image = dim + bright).
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) buffer Result { vec2 result[]; };               // padded, R + iG and B layers
layout(std430, binding = 1) readonly buffer Bright { vec4 bright[]; };       // x, y, then below
layout(std430, binding = 2) readonly buffer BrightValues { vec4 values[]; }; // R, G, B, unused
layout(std430, binding = 3) readonly buffer Kernel { float kernel[]; };      // K x K per channel, centre K/2
uniform int uWidth;
uniform int uHeight;
uniform int uPaddedWidth;
uniform int uLayerSize;
uniform int uKernelSize;
uniform int uKernelLayers;
uniform int uBrightCount;
uniform ivec2 uOrigin;  // the dispatch covers the bright pixels' box grown by the PSF's reach, from here

void main() {
  const ivec2 pixel = uOrigin + ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= uWidth || pixel.y >= uHeight) return;
  const int half_kernel = uKernelSize / 2;
  const int kernel_count = uKernelSize * uKernelSize;
  vec3 sum = vec3(0.0);
  for (int i = 0; i < uBrightCount; ++i) {
    const ivec2 offset = pixel - ivec2(bright[i].xy) + ivec2(half_kernel);
    if (offset.x < 0 || offset.y < 0 || offset.x >= uKernelSize || offset.y >= uKernelSize) continue;
    const int k = offset.y * uKernelSize + offset.x;
    const vec3 psf = uKernelLayers == 1 ? vec3(kernel[k])
                                        : vec3(kernel[k], kernel[kernel_count + k], kernel[2 * kernel_count + k]);
    sum += values[i].rgb * psf;
  }
  const int index = pixel.y * uPaddedWidth + pixel.x;
  result[index] += sum.rg;
  result[uLayerSize + index].x += sum.b;
}
