#version 450
// Convolution theorem: the spectrum of image * PSF is the pointwise product of their spectra
// (Ritschel et al. 2009, section 5, "Convolution"). The product goes into a buffer of its own, so
// both spectra stay for the next frame (glare/gl/convolution.h).
//
// The real layers come packed two to a complex layer: the image as Z0 = F(R + iG) and Z1 = F(B), a
// three-channel PSF as Q0 = F(K_R + iK_G) and Q1 = F(K_B), a one-channel (Y) PSF as Q0 = F(K). The
// spectrum of a real layer is Hermitian, F(x)[-k] = conj(F(x)[k]), so a packed pair comes apart at
// each frequency k from Z[k] and Z[-k] (-k taken modulo the grid on each axis):
//   F(R)[k] = (Z0[k] + conj(Z0[-k])) / 2,   F(G)[k] = (Z0[k] - conj(Z0[-k])) / 2i.
// The product is packed the same way, P0 = F(R) F(K_R) + i F(G) F(K_G) and P1 = F(B) F(K_B): the
// inverse of P0 is R*K_R + i G*K_G, both real, so its real and imaginary parts are the two results.
// With a one-channel PSF the separation is not needed: P0 = Z0 Q0 is (F(R) + i F(G)) F(K).
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Image { vec2 image[]; };    // Z0, Z1
layout(std430, binding = 1) readonly buffer Kernel { vec2 kernel[]; };  // Q0 (and Q1)
layout(std430, binding = 2) writeonly buffer Product { vec2 product[]; };  // P0, P1
uniform uint uPaddedWidth;
uniform uint uPaddedHeight;
uniform uint uKernelChannels;  // 1 or 3

vec2 complex_multiply(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 conjugate(vec2 a) { return vec2(a.x, -a.y); }
vec2 times_i(vec2 a) { return vec2(-a.y, a.x); }

// The spectra of the real and the imaginary part of a packed layer at k, from Z[k] and Z[-k].
vec2 real_part_spectrum(vec2 at_k, vec2 at_minus_k) { return 0.5 * (at_k + conjugate(at_minus_k)); }
vec2 imaginary_part_spectrum(vec2 at_k, vec2 at_minus_k) { return -0.5 * times_i(at_k - conjugate(at_minus_k)); }

void main() {
  // Grid-stride over one layer's elements: the host dispatches at most kMaxMultiplyGroups
  // (glare/gl/convolution.cpp; OpenGL guarantees 65535 groups per dimension, a 4096 x 4096 layer
  // would need 65536).
  const uint layer = uPaddedWidth * uPaddedHeight;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint element = gl_GlobalInvocationID.x; element < layer; element += stride) {
    const vec2 z0 = image[element], z1 = image[layer + element];
    if (uKernelChannels == 1u) {
      const vec2 q = kernel[element];
      product[element] = complex_multiply(z0, q);
      product[layer + element] = complex_multiply(z1, q);
      continue;
    }
    const uint x = element % uPaddedWidth, y = element / uPaddedWidth;
    const uint mirrored = ((uPaddedHeight - y) % uPaddedHeight) * uPaddedWidth + (uPaddedWidth - x) % uPaddedWidth;
    const vec2 z0_mirrored = image[mirrored], q0 = kernel[element], q0_mirrored = kernel[mirrored];
    const vec2 red = complex_multiply(real_part_spectrum(z0, z0_mirrored), real_part_spectrum(q0, q0_mirrored));
    const vec2 green = complex_multiply(imaginary_part_spectrum(z0, z0_mirrored), imaginary_part_spectrum(q0, q0_mirrored));
    product[element] = red + times_i(green);
    product[layer + element] = complex_multiply(z1, kernel[layer + element]);
  }
}
