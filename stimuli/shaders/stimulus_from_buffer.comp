#version 450
// A frame left on the GPU by the GL frame engine (stimuli/frame_engine.h) written into a rectangle
// of the stimulus framebuffer's RGBA32F texture (stimuli/frame_renderer.h): the buffer holds
// width x height RGBA pixels row 0 at the top (core/image.h's layout), the texture's rows start at
// the bottom. A copy: the values are the buffer's floats, alpha included.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Frame { vec4 pixels[]; };
layout(rgba32f, binding = 0) uniform writeonly image2D uStimulus;
uniform ivec2 uOrigin;        // the rectangle's top-left pixel in the stimulus, row 0 at the top
uniform ivec2 uSize;          // the rectangle's (and the buffer's) width and height
uniform int uStimulusHeight;  // the stimulus texture's height

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uSize.x || p.y >= uSize.y) return;
  const vec4 value = pixels[p.y * uSize.x + p.x];
  imageStore(uStimulus, ivec2(uOrigin.x + p.x, uStimulusHeight - 1 - (uOrigin.y + p.y)), value);
}
