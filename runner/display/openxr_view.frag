#version 450 core
// One eye's half of the side-by-side frame into its view's swapchain image
// (runner/display/openxr_views.cpp). The frame holds drive values, already through the
// experiment's display encoding; an sRGB image stores them as they are (written with
// GL_FRAMEBUFFER_SRGB off, so the runtime's sRGB decode and the panel's encode give them back). A
// float image is linear to the runtime, which encodes it with the sRGB curve for the panel: it
// gets the drive values decoded by that curve (IEC 61966-2-1, the piecewise EOTF with the 0.04045
// threshold), so the panel again receives the drive values.
layout(binding = 0) uniform sampler2D frame;
uniform int left_px;
uniform int to_linear;
out vec4 colour;

void main() {
  vec3 drive = texelFetch(frame, ivec2(gl_FragCoord.xy) + ivec2(left_px, 0), 0).rgb;
  if (to_linear != 0) {
    vec3 d = clamp(drive, 0.0, 1.0);
    drive = mix(d / 12.92, pow((d + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), d));
  }
  colour = vec4(drive, 1.0);
}
