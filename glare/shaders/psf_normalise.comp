#version 450
// Divides every channel by its sum, so each PSF channel sums to 1 (issue 3; the paper's K).
layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Values { float values[]; };
layout(std430, binding = 1) readonly buffer Sums { float sums[]; };  // one per channel
uniform uint uCount;  // values per channel

void main() {
  const uint index = gl_GlobalInvocationID.x;
  if (index >= uCount) return;
  const uint channel = gl_GlobalInvocationID.y;
  const float sum = sums[channel];
  if (sum > 0.0) values[channel * uCount + index] /= sum;
}
