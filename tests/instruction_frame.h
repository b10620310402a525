#pragma once
// Whether a saved stimulus frame (linear cd/m2, e.g. from run --save-frames) shows a given text
// centred on the screen: the text rasterised on its own (stimuli/text_image.h, white on a black
// background scaled to the text luminance) is looked for at the centre of the frame, where
// [presentation] places centred text, within a few pixels either way.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/image.h"
#include "stimuli/text_image.h"

namespace glarelab::test {

// The smallest, over offsets of up to `search_px` from the centred position, of the largest
// difference (cd/m2, any channel) between the frame and the text block; infinity when the block
// does not fit. A frame on a black background that shows the text there gives (nearly) 0.
inline double centred_text_mismatch_cd_m2(const ImageRGBA& frame, const std::string& text, double line_height_px,
                                          double max_width_px, double text_cd_m2, int search_px = 2) {
  TextImageStyle style;
  style.line_height_px = line_height_px;
  style.max_width_px = max_width_px;
  style.text_cd_m2 = text_cd_m2;
  style.background_cd_m2 = 0.0;
  const ImageRGBA block = render_text_image(text, style);
  const int x_centre = (frame.width_px - block.width_px) / 2;
  const int y_centre = (frame.height_px - block.height_px) / 2;
  double best = std::numeric_limits<double>::infinity();
  for (int dy = -search_px; dy <= search_px; ++dy)
    for (int dx = -search_px; dx <= search_px; ++dx) {
      const int x0 = x_centre + dx, y0 = y_centre + dy;
      if (x0 < 0 || y0 < 0 || x0 + block.width_px > frame.width_px || y0 + block.height_px > frame.height_px) continue;
      double worst = 0.0;
      for (int y = 0; y < block.height_px && worst < best; ++y)
        for (int x = 0; x < block.width_px; ++x)
          for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(static_cast<double>(frame.pixel(x0 + x, y0 + y)[c]) -
                                             static_cast<double>(block.pixel(x, y)[c])));
      best = std::min(best, worst);
    }
  return best;
}

}  // namespace glarelab::test
