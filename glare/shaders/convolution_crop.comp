#version 450
// The image-sized window of the convolved layers (R + iG and B) back into an RGBA image, the alpha of
// the input passed through: only the result crosses the bus.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Padded { vec2 padded[]; };  // R + iG and B layers, row-major
layout(std430, binding = 1) readonly buffer Image { vec4 image[]; };    // the input, for alpha
layout(std430, binding = 2) writeonly buffer Result { vec4 result[]; }; // width x height RGBA
uniform int uWidth;
uniform int uHeight;
uniform int uPaddedWidth;
uniform int uPaddedHeight;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uWidth || p.y >= uHeight) return;
  const int layer = uPaddedWidth * uPaddedHeight;
  const int index = p.y * uPaddedWidth + p.x;
  const int pixel = p.y * uWidth + p.x;
  result[pixel] = vec4(padded[index], padded[layer + index].x, image[pixel].a);
}
