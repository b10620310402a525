#version 450
// Divides every channel by its sum, so each PSF channel sums to 1 (the paper's K).
// Grid-stride loop: a 4096^2 channel has 65536 groups of 256 values, one more than the 65535
// work groups per dimension OpenGL guarantees (GL_MAX_COMPUTE_WORK_GROUP_COUNT), so the host
// dispatches at most kMaxNormaliseGroups (glare/gl/psf.cpp) and each invocation strides over the channel.
layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Values { float values[]; };
layout(std430, binding = 1) readonly buffer Sums { float sums[]; };  // one per channel
uniform uint uCount;  // values per channel

void main() {
  const uint channel = gl_GlobalInvocationID.y;
  const float sum = sums[channel];
  if (!(sum > 0.0)) return;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint index = gl_GlobalInvocationID.x; index < uCount; index += stride) values[channel * uCount + index] /= sum;
}
