#version 450 core
// Copies a scene (linear Rec.709 RGB, Y in cd/m2 after scaling) into the stimulus framebuffer.
// Image row 0 (the top) was uploaded first, so it sits at texture coordinate t = 0.
// Overlays (uOverlay = 1) are premultiplied (rgb = cd/m2 x coverage, a = coverage) and keep their
// alpha for the "over" blend; scenes are opaque.
layout(binding = 0) uniform sampler2D uScene;
uniform float uScale;  // cd/m2 per stored unit
uniform int uOverlay;
in vec2 vUv;
out vec4 fragColor;

void main() {
  vec4 texel = texelFetch(uScene, ivec2(vUv * vec2(textureSize(uScene, 0))), 0);
  fragColor = vec4(texel.rgb * uScale, uOverlay == 1 ? texel.a : 1.0);
}
