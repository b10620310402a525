#version 450 core
// Draws a rectangle given in pixels (origin top-left, as in every glarelab image) as a triangle
// strip of four vertices generated from gl_VertexID, so no vertex buffer is needed.
uniform vec4 uRectPx;      // x, y (top-left), width, height in framebuffer pixels
uniform vec2 uViewportPx;  // framebuffer width, height in pixels
out vec2 vUv;              // (0,0) at the image's top-left corner

void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
  vec2 pixel = uRectPx.xy + corner * uRectPx.zw;
  vUv = corner;
  gl_Position = vec4(pixel.x / uViewportPx.x * 2.0 - 1.0, 1.0 - pixel.y / uViewportPx.y * 2.0, 0.0, 1.0);
}
