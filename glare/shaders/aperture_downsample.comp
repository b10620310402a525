#version 450
// Box filter: each aperture texel is the mean transmittance of its s x s samples (Ritschel et al.
// 2009, section 5: primitives drawn with 2 x 2 or more supersampling against aliasing in the FFT).
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = 0) uniform readonly image2D uSamples;
layout(r32f, binding = 1) uniform writeonly image2D uAperture;
uniform int uSize;           // N
uniform int uSupersampling;  // s

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= uSize || texel.y >= uSize) return;
  float sum = 0.0;
  for (int dy = 0; dy < uSupersampling; ++dy)
    for (int dx = 0; dx < uSupersampling; ++dx) sum += imageLoad(uSamples, texel * uSupersampling + ivec2(dx, dy)).r;
  imageStore(uAperture, texel, vec4(sum / float(uSupersampling * uSupersampling)));
}
