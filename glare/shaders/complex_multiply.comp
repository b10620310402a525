#version 450
// Convolution theorem: the spectrum of image * PSF is the pointwise product of their spectra
// (Ritschel et al. 2009, section 5, "Convolution"). Image layers are R, G, B; a one-channel (Y)
// PSF multiplies all three. The product goes into a buffer of its own, so both spectra stay for
// the next frame (glare/gl/convolution.h).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Image { vec2 image[]; };
layout(std430, binding = 1) readonly buffer Kernel { vec2 kernel[]; };
layout(std430, binding = 2) writeonly buffer Product { vec2 product[]; };
uniform uint uLayerSize;   // padded width * height
uniform uint uImageLayers;
uniform uint uKernelLayers;  // 1 or uImageLayers

void main() {
  // Grid-stride: the host dispatches at most kMaxMultiplyGroups (glare/gl/convolution.cpp; OpenGL
  // guarantees 65535 groups per dimension, three 4096 x 4096 layers would need 196608).
  const uint total = uLayerSize * uImageLayers;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint index = gl_GlobalInvocationID.x; index < total; index += stride) {
    const vec2 a = image[index];
    const vec2 b = kernel[uKernelLayers == 1u ? index % uLayerSize : index];
    product[index] = vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
  }
}
