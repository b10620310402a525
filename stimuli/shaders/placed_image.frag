#version 450 core
// Copies a scene (linear Rec.709 RGB, Y in cd/m2 after scaling) into the stimulus framebuffer.
// Image row 0 (the top) was uploaded first, so it sits at texture coordinate t = 0.
layout(binding = 0) uniform sampler2D uScene;
uniform float uScale;  // cd/m2 per stored unit
in vec2 vUv;
out vec4 fragColor;

void main() {
  vec3 rgb = texelFetch(uScene, ivec2(vUv * vec2(textureSize(uScene, 0))), 0).rgb;
  fragColor = vec4(rgb * uScale, 1.0);
}
