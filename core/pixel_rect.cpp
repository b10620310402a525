#include "core/pixel_rect.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace glarelab {

PixelRect image_rect(const ImageRGBA& image) { return PixelRect{0, 0, image.width_px, image.height_px}; }

PixelRect intersection(const PixelRect& a, const PixelRect& b) {
  const int x0 = std::max(a.x_px, b.x_px), y0 = std::max(a.y_px, b.y_px);
  const int x1 = std::min(a.right_px(), b.right_px()), y1 = std::min(a.bottom_px(), b.bottom_px());
  if (x1 <= x0 || y1 <= y0) return PixelRect{a.x_px, a.y_px, 0, 0};
  return PixelRect{x0, y0, x1 - x0, y1 - y0};
}

PixelRect bounding_rect(const PixelRect& a, const PixelRect& b) {
  if (a.empty()) return b.empty() ? PixelRect{} : b;
  if (b.empty()) return a;
  const int x0 = std::min(a.x_px, b.x_px), y0 = std::min(a.y_px, b.y_px);
  const int x1 = std::max(a.right_px(), b.right_px()), y1 = std::max(a.bottom_px(), b.bottom_px());
  return PixelRect{x0, y0, x1 - x0, y1 - y0};
}

PixelRect bounding_rect(const std::vector<PixelRect>& rects) {
  PixelRect bound;
  for (const PixelRect& rect : rects) bound = bounding_rect(bound, rect);
  return bound;
}

ImageRGBA crop(const ImageRGBA& image, const PixelRect& rect) {
  const PixelRect inside = intersection(rect, image_rect(image));
  if (inside.empty()) return ImageRGBA();
  ImageRGBA part(inside.width_px, inside.height_px);
  const auto width = static_cast<std::size_t>(inside.width_px);
  const bool depth = !image.depth.empty();
  if (depth) part.depth.resize(width * static_cast<std::size_t>(inside.height_px));
  for (int y = 0; y < inside.height_px; ++y) {
    std::copy_n(image.pixel(inside.x_px, inside.y_px + y), 4 * width, part.pixel(0, y));
    if (!depth) continue;
    const std::size_t from =
        static_cast<std::size_t>(inside.y_px + y) * static_cast<std::size_t>(image.width_px) + inside.x_px;
    std::copy_n(image.depth.begin() + static_cast<std::ptrdiff_t>(from), width,
                part.depth.begin() + static_cast<std::ptrdiff_t>(width * static_cast<std::size_t>(y)));
  }
  return part;
}

void paste(ImageRGBA& into, const ImageRGBA& image, const PixelRect& at) {
  if (at.width_px != image.width_px || at.height_px != image.height_px)
    throw std::invalid_argument("paste: a " + std::to_string(image.width_px) + " x " + std::to_string(image.height_px) +
                                " px image into a " + std::to_string(at.width_px) + " x " +
                                std::to_string(at.height_px) + " px rectangle");
  const PixelRect inside = intersection(at, image_rect(into));
  if (inside.empty()) return;
  const int dx = inside.x_px - at.x_px, dy = inside.y_px - at.y_px;  // where `inside` starts in `image`
  const auto width = static_cast<std::size_t>(inside.width_px);
  const bool depth = !into.depth.empty() && !image.depth.empty();
  for (int y = 0; y < inside.height_px; ++y) {
    std::copy_n(image.pixel(dx, dy + y), 4 * width, into.pixel(inside.x_px, inside.y_px + y));
    if (!depth) continue;
    const std::size_t from = static_cast<std::size_t>(dy + y) * static_cast<std::size_t>(image.width_px) + dx;
    const std::size_t to =
        static_cast<std::size_t>(inside.y_px + y) * static_cast<std::size_t>(into.width_px) + inside.x_px;
    std::copy_n(image.depth.begin() + static_cast<std::ptrdiff_t>(from), width,
                into.depth.begin() + static_cast<std::ptrdiff_t>(to));
  }
}

}  // namespace glarelab
