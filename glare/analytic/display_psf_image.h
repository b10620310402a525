#pragma once
// Display kernels (glare/analytic/display_glare_kernel.h, glare/analytic/hybrid_psf.h) as PSF images for a file: a square grid
// of even side centred on pixel (size/2, size/2), each channel normalised to unit sum. The sum
// counts only the light within the image: what the kernel puts beyond its edges is left out, so
// the image is the PSF of a display of that size, not the eye's whole PSF.
#include "glare/analytic/display_glare_kernel.h"
#include "glare/wave/psf.h"

namespace glarelab {

// A flat display whose centre pixel subtends degrees_per_pixel: only the ratio of pitch to distance
// matters, so the distance is fixed at 1000 mm and the pitch is 1000 tan(degrees_per_pixel) mm.
DisplayGeometry flat_display_geometry(double degrees_per_pixel);

// An analytic PSF on size_px x size_px pixels of flat_display_geometry(degrees_per_pixel): each
// pixel its pixel_energy, the CIE peak at the centre, then unit sum per channel (3 channels when
// the PSF is chromatic, else 1). size_px even.
Psf analytic_psf_image(const AnalyticPsf& psf, double degrees_per_pixel, int size_px, int threads = 2);

// The hybrid kernel H = near + far (glare/analytic/hybrid_psf.h) on size_px x size_px pixels, near's centre on
// the image's, unit sum per channel (3 channels). The far kernel's half sizes must reach size_px / 2.
Psf hybrid_psf_image(const Psf& near, const DisplayKernel& far, double degrees_per_pixel, int size_px);

}  // namespace glarelab
