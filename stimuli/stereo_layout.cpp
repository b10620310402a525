#include "stimuli/stereo_layout.h"

#include <algorithm>
#include <stdexcept>

#include "core/random.h"

namespace glarelab {

const char* to_string(StereoMode mode) { return mode == StereoMode::side_by_side ? "side_by_side" : "none"; }

std::vector<EyeView> stereo_eye_views(const DisplaySpec& display) {
  if (display.stereo == StereoMode::none) return {};
  if (display.width_px % 2 != 0)
    throw std::invalid_argument("stereo layout: side_by_side needs an even display width, found " +
                                std::to_string(display.width_px));
  const int half_px = display.width_px / 2;
  return {EyeView{1, "left", {0, 0, half_px, display.height_px}},
          EyeView{0, "right", {half_px, 0, half_px, display.height_px}}};
}

DisplaySpec eye_display(const DisplaySpec& display, const EyeView& view) {
  DisplaySpec eye = display;
  eye.width_px = view.viewport.width_px;
  eye.height_px = view.viewport.height_px;
  eye.stereo = StereoMode::none;
  return eye;
}

std::uint64_t eye_seed(std::uint64_t session_seed, int tracker_eye) {
  const CounterRandom random(session_seed, RandomStream::stereo_eye);
  const auto bits = random.bits(static_cast<std::uint64_t>(tracker_eye));
  return (static_cast<std::uint64_t>(bits[0]) << 32) | bits[1];
}

std::vector<PixelRect> stereo_layout(const std::vector<EyeView>& views, const std::vector<PixelRect>& image_sizes,
                                     std::vector<PixelRect>* columns, int gap_px) {
  std::vector<PixelRect> placed;
  for (const EyeView& view : views) {
    std::vector<PixelRect> view_columns;
    const std::vector<PixelRect> rects =
        side_by_side_layout(view.viewport.width_px, view.viewport.height_px, image_sizes, &view_columns, gap_px);
    for (std::size_t i = 0; i < rects.size(); ++i) {
      PixelRect rect = rects[i], column = view_columns[i];
      rect.x_px += view.viewport.x_px, rect.y_px += view.viewport.y_px;
      column.x_px += view.viewport.x_px, column.y_px += view.viewport.y_px;
      placed.push_back(rect);
      if (columns) columns->push_back(column);
    }
  }
  return placed;
}

std::string stereo_misfit(const DisplaySpec& display, const std::vector<PixelRect>& image_sizes,
                          const std::vector<std::string>& names) {
  if (display.stereo == StereoMode::none || image_sizes.empty()) return {};
  const EyeView view = stereo_eye_views(display).front();
  std::vector<PixelRect> columns;
  side_by_side_layout(view.viewport.width_px, view.viewport.height_px, image_sizes, &columns, stimulus_gap_px(display));
  for (std::size_t i = 0; i < image_sizes.size(); ++i) {
    const PixelRect& size = image_sizes[i];
    if (size.width_px <= columns[i].width_px && size.height_px <= columns[i].height_px) continue;
    const std::string name = i < names.size() ? "'" + names[i] + "' " : "";
    const std::string shown = image_sizes.size() == 1 ? "" : " (" + std::to_string(image_sizes.size()) + " scenes side by side)";
    return "scene " + name + "(" + std::to_string(size.width_px) + " x " + std::to_string(size.height_px) +
           " px) does not fit its column of " + std::to_string(columns[i].width_px) + " x " +
           std::to_string(columns[i].height_px) + " px in each eye's half of the " + std::to_string(display.width_px) +
           " x " + std::to_string(display.height_px) + " px display" + shown +
           ": a stereo view must show each eye the whole scene. Use a wider display, smaller scenes, or stereo = "
           "\"none\"";
  }
  return {};
}

PixelRect moved_into_view(const PixelRect& rect, const DisplaySpec& display, const EyeView& view) {
  // Twice the centres, to stay in whole pixels: a view of even width on a display of even width.
  const int dx2 = 2 * view.viewport.x_px + view.viewport.width_px - display.width_px;
  const int dy2 = 2 * view.viewport.y_px + view.viewport.height_px - display.height_px;
  return {rect.x_px + dx2 / 2, rect.y_px + dy2 / 2, rect.width_px, rect.height_px};
}

ImageRGBA crop_view(const ImageRGBA& frame, const PixelRect& viewport) {
  if (!image_rect(frame).contains(viewport))
    throw std::invalid_argument("stereo layout: the eye's view lies outside the frame");
  ImageRGBA view = crop(frame, viewport);
  view.depth.clear();  // colour only (stereo_layout.h)
  return view;
}

void paste_view(ImageRGBA& frame, const ImageRGBA& view_image, const PixelRect& viewport) {
  if (view_image.width_px != viewport.width_px || view_image.height_px != viewport.height_px ||
      !image_rect(frame).contains(viewport))
    throw std::invalid_argument("stereo layout: the eye's image does not match its view in the frame");
  paste(frame, view_image, viewport);
}

}  // namespace glarelab
