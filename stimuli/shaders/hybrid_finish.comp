#version 450
// The hybrid and human eyes' frame finished on the GPU (stimuli/gpu_hybrid_finish.h): the near
// part's convolution of the frame's energies (the GL glare backend's result) plus the far part's
// glare, plus the lenticular halo's ring less the source's own energy times the halo's share,
// divided by the pixel's relative solid angle (energy back to luminance): the per-pixel finish of
// stimuli/glare_stage_hybrid.cpp, in float. Alpha: the energies' (the frame's).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Near { vec4 near_energy[]; };
layout(std430, binding = 1) readonly buffer Far { vec4 far_energy[]; };
layout(std430, binding = 2) readonly buffer Ring { vec4 ring_energy[]; };
layout(std430, binding = 3) readonly buffer Energy { vec4 energy[]; };
layout(std430, binding = 4) readonly buffer Weight { float relative_solid_angle[]; };
layout(std430, binding = 5) writeonly buffer Result { vec4 result_cd_m2[]; };
uniform uint uPixels;
uniform int uHalo;          // 1: the ring is added
uniform float uHaloEnergy;  // the halo's share of the light (GlareFrameReport::halo_energy)

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= uPixels) return;
  vec3 value = near_energy[i].rgb + far_energy[i].rgb;
  if (uHalo != 0) value += uHaloEnergy * (ring_energy[i].rgb - energy[i].rgb);
  result_cd_m2[i] = vec4(value / relative_solid_angle[i], energy[i].a);
}
