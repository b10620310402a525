#version 450
// One level of a pairwise (tree) sum: each workgroup adds 512 consecutive values of one channel
// into one partial sum. Repeated until one value per channel is left. Pairwise summation keeps the
// rounding error at O(log n) ulps, so a 4096^2 PSF still sums to 1 within 1e-6 in single precision.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Values { float values[]; };
layout(std430, binding = 1) writeonly buffer Sums { float sums[]; };
uniform uint uCount;         // values per channel at this level
uniform uint uGroupsPerChannel;

shared float partial[256];

void main() {
  const uint local = gl_LocalInvocationID.x;
  const uint channel = gl_WorkGroupID.y;
  const uint first = gl_WorkGroupID.x * 512u + local;
  const uint base = channel * uCount;
  float value = first < uCount ? values[base + first] : 0.0;
  if (first + 256u < uCount) value += values[base + first + 256u];
  partial[local] = value;
  barrier();
  for (uint stride = 128u; stride > 0u; stride >>= 1u) {
    if (local < stride) partial[local] += partial[local + stride];
    barrier();
  }
  if (local == 0u) sums[channel * uGroupsPerChannel + gl_WorkGroupID.x] = partial[0];
}
