#pragma once
// Display kernels of the CIE 146 glare spread function (glare/analytic/display_glare_kernel.h) kept
// on disk between sessions. Integrating the kernel over a full screen's pixels (3839 x 2159 offsets
// at 1920 x 1080) takes seconds, and every session of the default eye (whose far field it is) and
// every `cie` row paid it again, with the same inputs and so the same result bit for bit.
//
// Key: every input the kernel depends on, written out exactly (hexadecimal floating point): the
// model, the observer's age, pigmentation and measured straylight, the viewing distance and pixel
// pitch, the kernel's half sizes, the file format's version, and a fingerprint of the formula: the
// energies of a few pixels (near the centre, at the CIE kink, far out, the corner) and the peak
// fraction, computed afresh each time (microseconds), so that any change to the quadrature or the
// glare spread function gives another key instead of an outdated kernel. The file name is a 64-bit
// hash of the key; the file holds the key itself, which must match in full.
//
// Written as the FFTW wisdom is (glare/cpu/fftw_wisdom.h): into a new file beside the entry (created
// exclusively, never through a symbolic link), flushed to disk, then renamed over the entry, so a
// reader sees the old entry or the new one, never half of one. Read back with a checksum over the
// whole file (header, key and values); a damaged, truncated or mismatched entry, or one that is a
// symbolic link, is recomputed with a warning on stderr and written again.
//
// Where: GLARELAB_KERNEL_CACHE if set (a folder; "none" keeps none), else
// $XDG_CACHE_HOME/glarelab/kernels, else ~/.cache/glarelab/kernels (beside the wisdom file). Kernels
// smaller than kCachedKernelMinimumPixels are not kept: they integrate in well under a second.
#include <string>

#include "glare/analytic/analytic_psf.h"
#include "glare/analytic/display_glare_kernel.h"

namespace glarelab {

struct KernelCachePlace {
  std::string folder;  // empty: none is kept
  std::string reason;  // why none is kept
  bool kept() const { return !folder.empty(); }
  // "display kernels kept in FOLDER" or "display kernels not kept (REASON)".
  std::string describe() const;
};

// The place for this process: from the environment on first use, or the last use_kernel_cache_folder().
KernelCachePlace kernel_cache_place();
// From now on this process keeps its kernels in `folder` ("" or "none": keeps none). The folder is
// made if need be; one that cannot be made gives a place with none kept and the reason.
void use_kernel_cache_folder(const std::string& folder);

inline constexpr long long kCachedKernelMinimumPixels = 1LL << 18;

enum class KernelCacheOutcome { not_kept, read, stored, recomputed };

// analytic_display_kernel(psf, geometry, half_width_px, half_height_px, threads) for a CIE PSF, read
// from the cache when it holds a whole entry of exactly these inputs, else computed and stored
// (kernels of other models, or of fewer than minimum_pixels offsets, are computed and not kept).
// `outcome` (optional) says which; `recomputed`: an entry was there but damaged or mismatched.
DisplayKernel cached_analytic_display_kernel(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                             int half_height_px, int threads = 2,
                                             long long minimum_pixels = kCachedKernelMinimumPixels,
                                             KernelCacheOutcome* outcome = nullptr);

// The entry's file for these inputs (whether or not it exists); empty when no place is kept.
std::string kernel_cache_entry_path(const AnalyticPsf& psf, const DisplayGeometry& geometry, int half_width_px,
                                    int half_height_px);

}  // namespace glarelab
