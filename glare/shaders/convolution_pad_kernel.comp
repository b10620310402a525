#version 450
// The PSF into the padded FFT grid with its centre (K/2, K/2) at index (0, 0), wrapping: grid
// (x, y) holds PSF (u, v) = ((x + K/2) mod W, (y + K/2) mod H) where that lies inside the K x K PSF,
// else zero. Circular convolution then equals linear convolution on the image window because the
// padding is at least K - 1 (glare/gl/convolution.cpp). A three-channel PSF goes into two complex
// layers, K_R + iK_G and K_B; a one-channel PSF into one, K.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) writeonly buffer Padded { vec2 padded[]; };  // (uKernelLayers + 1) / 2 layers
layout(std430, binding = 1) readonly buffer Kernel { float kernel[]; };  // K x K per channel, row-major
uniform int uPaddedWidth;
uniform int uPaddedHeight;
uniform int uKernelSize;
uniform int uKernelLayers;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uPaddedWidth || p.y >= uPaddedHeight) return;
  const int u = (p.x + uKernelSize / 2) % uPaddedWidth;
  const int v = (p.y + uKernelSize / 2) % uPaddedHeight;
  const bool inside = u < uKernelSize && v < uKernelSize;
  const int layer = uPaddedWidth * uPaddedHeight;
  const int index = p.y * uPaddedWidth + p.x;
  const int kernel_count = uKernelSize * uKernelSize;
  const int at = v * uKernelSize + u;
  if (uKernelLayers == 1) {
    padded[index] = vec2(inside ? kernel[at] : 0.0, 0.0);
  } else {
    padded[index] = inside ? vec2(kernel[at], kernel[kernel_count + at]) : vec2(0.0);
    padded[layer + index] = vec2(inside ? kernel[2 * kernel_count + at] : 0.0, 0.0);
  }
}
