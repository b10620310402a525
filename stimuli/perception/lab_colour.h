#pragma once
// CIE 1976 L*a*b* of luminance-calibrated linear Rec.709 RGB (cd/m2), for the acuity loss of
// Luidolt 2020 section 5.3 (after Krawczyk et al. 2005), which blurs L* and keeps a*, b*.
//
// Reference white. Lab needs a white (X_n, Y_n, Z_n) and the thesis leaves Y_n implicit. Its
// numbers fix it: section 5.3.2 inverts Eq. 5.14 at the headset's 13.85 pixels per degree and finds
// "approximately 1.31 L". Eq. 5.14 gives R = 13.85 cycles/degree at Y = 0.1455 cd/m2, and
// L* = 903.3 Y / Y_n is 1.314 for Y_n = 100 cd/m2 (the Y_n that gives 1.31 exactly is 100.3).
// With Y_n = 1 (scene units taken as relative) the same Y would be L* = 45 and the thesis' 1.31
// could not arise. So Y_n = 100 cd/m2, also the conventional white of a display-referred image, is
// the default (`reference_white_cd_m2`); Eq. 5.16's "no blur where L >= 1" then blurs pixels below
// Y = 100 / 903.3 = 0.111 cd/m2, the mesopic-scotopic range where acuity falls. The chromaticity
// is Rec.709's D65 white, R = G = B, so a grey pixel has a* = b* = 0 exactly.
//
// Matrices: linear Rec.709 to XYZ from the Rec.709 primaries and D65 (IEC 61966-2-1), and its
// inverse, in double precision.
namespace glarelab {

// Linear Rec.709 (D65) to CIE XYZ and back, from the primaries and white of IEC 61966-2-1.
inline constexpr double kRec709ToXyz[3][3] = {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
                                              {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
                                              {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}};
inline constexpr double kXyzToRec709[3][3] = {{3.24096994190452134, -1.53738317757009346, -0.49861076029300328},
                                              {-0.96924363628087983, 1.87596750150772067, 0.04155505740717561},
                                              {0.05563007969699361, -0.20397695888897657, 1.05697151424287856}};

struct LabColour {
  double lightness = 0.0;  // L*, 0 (black) .. 100 (the reference white)
  double a = 0.0;
  double b = 0.0;
};

// CIE L* of a luminance: 116 f(Y / Y_n) - 16, f(t) = cbrt(t) above (6/29)^3, else
// t / (3 (6/29)^2) + 4/29 (so L* = 903.3 Y / Y_n in the dark).
double lab_lightness(double luminance_cd_m2, double reference_white_cd_m2);
// The inverse ("LtoY" of Luidolt Eq. 5.15): the luminance in cd/m2 of a lightness L*.
double luminance_of_lab_lightness(double lightness, double reference_white_cd_m2);

LabColour rec709_to_lab(double r, double g, double b, double reference_white_cd_m2);
// Writes linear Rec.709 (cd/m2) to rgb[0..2].
void lab_to_rec709(const LabColour& lab, double reference_white_cd_m2, double rgb[3]);

// The pixel rgb[0..2] (linear Rec.709, cd/m2) with its L* replaced by `lightness` and its a*, b*
// kept: lab_to_rec709 of rec709_to_lab with the new L*, in double, rounded to float once. Each f is
// carried as f - 4/29, which on the linear branch has no cancellation near black (the plain
// f - 4/29 would lose 1e-4 of a 0.01 cd/m2 pixel in float); Y's becomes L* / 116, and X's and Z's
// move by as much.
void replace_lab_lightness(float* rgb, double lightness, double reference_white_cd_m2);

}  // namespace glarelab
