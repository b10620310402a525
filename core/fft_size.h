#pragma once
// FFT lengths with small prime factors only: what a padded FFT convolution rounds its grid up to,
// glare's (glare/cpu/convolution.*, glare/cpu/float_convolution.*) and the depth of field's
// (stimuli/depth_of_field_blur.*) alike. FFTW transforms any length, but one with a large prime
// factor falls back to slower codelets.

namespace glarelab {

// Smallest n' >= max(n, 1) whose prime factors are 2, 3, 5 and 7 (sizes FFTW handles fastest).
int good_fft_size(int n);
// Smallest n' >= max(n, 1) whose prime factors are 2, 3 and 5: without 7, whose codelets FFTW runs
// slower per value (docs/PERFORMANCE.md, "2,3,5-smooth sizes").
int smooth_fft_size(int n);

}  // namespace glarelab
