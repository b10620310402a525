#version 450
// One glaring position's part of a layered glare frame on the GPU (stimuli/position_glare.h):
// frame += glared layer - layer over R, G, B, alpha kept. Run once per glaring layer on the
// composed frame, it makes composed - sum(layers) + sum(glared layers), apply_layered_glare's sum.
layout(local_size_x = 256) in;
layout(std430, binding = 0) buffer Frame { vec4 frame[]; };
layout(std430, binding = 1) readonly buffer Layer { vec4 layer[]; };
layout(std430, binding = 2) readonly buffer Glared { vec4 glared[]; };
uniform uint uPixels;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= uPixels) return;
  frame[i].rgb = frame[i].rgb - layer[i].rgb + glared[i].rgb;
}
