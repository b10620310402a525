#pragma once
// Scotopic colour vision (Luidolt 2020, section 5.4, after Krawczyk et al. 2005), after tone
// mapping, weighted by the rod sensitivity sigma(L_i) = 0.04 / (0.04 + L_i) of the temporally
// adapted luminance L_i (Eq. 5.4; L_i in cd/m2, before tone mapping):
//   SV = RGB (1 - sigma(L_i)) + [1.05, 0.97, 1.27] L'_i sigma(L_i)                     (Eq. 5.18)
// with RGB the tone-mapped colour and L'_i its luminance (Eq. 5.1 weights), both in display
// cd/m2 here. The tint's own luminance is 1.0086 (Eq. 5.1), so full rod vision keeps a pixel's
// luminance within 1 % and turns it lavender; the blue channel can then exceed the display peak
// by up to 27 % of L' and is clipped by the display encoding like any other value.
//
// The alternative of Spencer et al. 1995 (section 5, their Fig. 14): "the saturation in HSV space
// was reduced by 70 % to simulate scotopic (rod) vision". Spencer applied it to scotopic images
// outright; here the reduction is weighted by the same rod sensitivity, S' = S (1 - 0.7 sigma(L_i)),
// so it is 70 % in full rod vision and vanishes in daylight. Hue and value (the largest channel)
// are kept: with V and H fixed every channel is V - (V - c) S' / S.
#include "core/image.h"
#include "core/perception_settings.h"

namespace glarelab {

// Throws std::invalid_argument naming the field and its accepted range.
void validate_scotopic_settings(const ScotopicSettings& settings);

// One pixel, rgb in and out (display cd/m2); rod_sensitivity in [0, 1] (Eq. 5.4 at L_i).
void luidolt_scotopic_pixel(const double rgb[3], double rod_sensitivity, double out[3]);
void spencer_desaturate_pixel(const double rgb[3], double saturation_reduction, double out[3]);

// The frame (alpha kept), from the rod sensitivity of the adapted luminance.
ImageRGBA apply_scotopic_colour(const ImageRGBA& tone_mapped, double rod_sensitivity,
                                const ScotopicSettings& settings);

}  // namespace glarelab
