#version 450
// The last step of the spectral PSF before normalisation (glare/wave/spectral_accumulation.h): R, G, B
// values below 0 (spectral colours outside the Rec.709 gamut) are clamped to 0.
layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Values { float values[]; };
uniform uint uCount;  // all values, every channel

void main() {
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint index = gl_GlobalInvocationID.x; index < uCount; index += stride) values[index] = max(values[index], 0.0);
}
