#include "stimuli/depth_of_field.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/parallel_for.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/depth_of_field_rows.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

// Kernels kept from frame to frame at most; past it the list starts again.
constexpr std::size_t kKeptKernels = 256;

// Each layer's span in each frame row from the rows' runs (DepthLayerPlan), spans[layer * height + y]
// in frame columns (first == last: none), each row's entries written by its own chunk.
void layer_row_spans(std::size_t layers, const std::vector<std::vector<PixelRun>>& runs, int threads,
                     std::vector<RowSpan>& spans) {
  const int height = static_cast<int>(runs.size());
  spans.assign(layers * static_cast<std::size_t>(height), RowSpan{});
  parallel_chunks(height, threads, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (const PixelRun& run : runs[static_cast<std::size_t>(y)])
        for (const std::uint32_t index : {run.own, run.blended}) {
          RowSpan& span = spans[index * static_cast<std::size_t>(height) + y];
          if (span.first == span.last) span.first = run.first;
          span.last = run.end;
        }
  });
}

FrameRectangle bounding_rectangle(const RowSpan* spans, int height) {
  FrameRectangle box{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), -1, -1};
  for (int y = 0; y < height; ++y) {
    if (spans[y].first >= spans[y].last) continue;
    box.x0 = std::min(box.x0, spans[y].first);
    box.x1 = std::max(box.x1, spans[y].last - 1);
    box.y0 = std::min(box.y0, y);
    box.y1 = std::max(box.y1, y);
  }
  return box;
}

void refuse(const std::string& what) { throw std::invalid_argument("stimuli/depth_of_field: " + what); }

// The checks of check_depth_of_field_inputs before its pixels' and depths'.
void check_image_and_settings(const ImageRGBA& image_cd_m2, const DepthOfFieldSettings& settings) {
  if (image_cd_m2.empty()) refuse("the image is empty");
  if (!(settings.degrees_per_pixel > 0.0) || !std::isfinite(settings.degrees_per_pixel))
    refuse("degrees per pixel " + std::to_string(settings.degrees_per_pixel) + " must be positive and finite");
  if (!(settings.pupil_radius_m > 0.0) || !std::isfinite(settings.pupil_radius_m))
    refuse("the pupil radius " + std::to_string(settings.pupil_radius_m) + " m must be positive and finite");
  if (!(settings.tolerance_px > 0.0) || !std::isfinite(settings.tolerance_px))
    refuse("the layer tolerance " + std::to_string(settings.tolerance_px) + " px must be positive and finite");
  if (settings.threads < 1) refuse("threads " + std::to_string(settings.threads) + " must be at least 1");
  if (!settings.residual_error) refuse("no eye error function was given");
}

void refuse_pixels(const ImageRGBA& image_cd_m2) {
  const NonFiniteReport pixels = inspect_pixels(image_cd_m2);
  if (!pixels.clean()) refuse("the image has " + pixels.describe() + "; luminances must be finite and non-negative");
}

// The kernel of `ellipse`, made once and kept for the frames after: a scene's layers keep their
// ellipses from frame to frame, and 256 coverage samples a tap made the kernels about 1 % of the
// stage's time on the whole-frame bench.
const EllipticalKernel& kept_kernel(std::vector<std::pair<PixelBlurEllipse, EllipticalKernel>>& kept,
                                    const PixelBlurEllipse& ellipse) {
  for (const auto& [kept_ellipse, kernel] : kept)
    if (kept_ellipse.semi_major_px == ellipse.semi_major_px && kept_ellipse.semi_minor_px == ellipse.semi_minor_px &&
        kept_ellipse.major_axis_angle_deg == ellipse.major_axis_angle_deg)
      return kernel;
  if (kept.size() >= kKeptKernels) kept.clear();
  return kept.emplace_back(ellipse, elliptical_kernel(ellipse)).second;
}

// The rows of `box` in its own columns (the layer's rectangle), from the frame's spans.
std::vector<RowSpan> box_row_spans(const RowSpan* frame_spans, const FrameRectangle& box) {
  std::vector<RowSpan> spans(static_cast<std::size_t>(box.y1 - box.y0 + 1));
  for (int y = box.y0; y <= box.y1; ++y) {
    const RowSpan& span = frame_spans[y];
    if (span.first < span.last) spans[static_cast<std::size_t>(y - box.y0)] = {span.first - box.x0, span.last - box.x0};
  }
  return spans;
}

// A layer blurred whole by FFT before the tiles, its blurred rows kept in `stored` (the FFT's grids
// are the layer's whole padded rectangle: no tile could hold them). Returns whether every pixel
// read was in range.
bool blur_whole_layer_by_fft(const ImageRGBA& image, DepthOfFieldBuffers& buffers, std::uint32_t index,
                             const FrameRectangle& box, const EllipticalKernel& kernel, int threads,
                             VectorIsa isa, BlurredLayerRows& stored) {
  LayerRows& rows = buffers.rows;
  const bool in_range = fill_layer_rows(image, buffers.row_runs, index, box, box.y0, box.y1, kernel, rows, threads, isa);
  stored.x0_px = box.x0 - kernel.radius_x_px;
  stored.y0_px = box.y0 - kernel.radius_y_px;
  stored.spans = blurred_row_spans(rows.spans, kernel);
  stored.offsets.resize(stored.spans.size());
  std::size_t size = 0;
  for (std::size_t row = 0; row < stored.spans.size(); ++row) {
    stored.offsets[row] = size;
    size += 4 * static_cast<std::size_t>(std::max(0, stored.spans[row].last - stored.spans[row].first));
  }
  stored.rgba.resize(size);
  blur_rows_fft(
      rows, kernel, threads,
      [&](int row, int, int count, const float* rgba) {
        std::copy_n(rgba, 4 * static_cast<std::size_t>(count),
                    stored.rgba.data() + stored.offsets[static_cast<std::size_t>(row)]);
      },
      buffers.fft);
  return in_range;
}

}  // namespace

void check_depth_of_field_inputs(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                 const DepthOfFieldSettings& settings) {
  check_image_and_settings(image_cd_m2, settings);
  refuse_pixels(image_cd_m2);
  check_scene_depth(depth_m, image_cd_m2.width_px, image_cd_m2.height_px, "the depth map");
}

ImageRGBA apply_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                               const DepthOfFieldSettings& settings, DepthOfFieldReport* report) {
  DepthOfFieldBuffers buffers;
  ImageRGBA result;
  apply_depth_of_field(image_cd_m2, depth_m, settings, buffers, result, report);
  return result;
}

void apply_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                          const DepthOfFieldSettings& settings, DepthOfFieldBuffers& buffers, ImageRGBA& result,
                          DepthOfFieldReport* report) {
  // check_depth_of_field_inputs' checks, the pixels' as the layers read them (fill_layer_rows): a
  // bad pixel is refused with its message once the layers are filled.
  check_image_and_settings(image_cd_m2, settings);
  check_scene_depth(depth_m, image_cd_m2.width_px, image_cd_m2.height_px, "the depth map");
  if (&result == &image_cd_m2) refuse("the result cannot be written over its own input image");
  const int width = image_cd_m2.width_px, height = image_cd_m2.height_px;
  const BlurGeometry geometry{settings.degrees_per_pixel, settings.pupil_radius_m};
  plan_depth_layer_runs(depth_m, width, height, geometry, settings.residual_error, settings.tolerance_px,
                        settings.threads, buffers.plan, buffers.row_runs);
  const DepthLayerPlan& plan = buffers.plan;
  layer_row_spans(plan.layers.size(), buffers.row_runs, settings.threads, buffers.layer_spans);
  const std::vector<RowSpan>& frame_spans = buffers.layer_spans;
  const std::size_t layer_count = plan.layers.size();

  DepthOfFieldReport counts;
  counts.layers = static_cast<int>(layer_count);
  const double pixels_per_dioptre = geometry.pixels_per_dioptre();
  // Each layer's kernel (a layer within its pixel passes through: the identity kernel's sum is each
  // value itself), its rectangle, its method and whether it hides farther layers.
  std::vector<EllipticalKernel> kernels(layer_count);
  std::vector<DirectSumKernel> direct(layer_count);
  std::vector<TiledLayer> layers(layer_count);
  buffers.fft_rows.resize(layer_count);
  bool in_range = true;
  for (std::size_t index = 0; index < layer_count; ++index) {
    const DepthLayer& plan_layer = plan.layers[index];
    counts.max_blur_error_px = std::max(counts.max_blur_error_px, plan_layer.max_blur_error_px);
    kernels[index] = plan_layer.blurred ? kept_kernel(buffers.kernels, plan_layer.ellipse)
                                        : EllipticalKernel{0, 0, {1.0}, 1.0};
    const EllipticalKernel& kernel = kernels[index];
    TiledLayer& layer = layers[index];
    layer.vergence_dioptres = plan_layer.vergence_dioptres;
    layer.kernel = &kernel;
    const RowSpan* spans = &frame_spans[index * static_cast<std::size_t>(height)];
    layer.box = bounding_rectangle(spans, height);
    if (layer.box.x1 < 0) continue;  // no pixel (a layer is made only for depths the scene has)
    // Layers that blend (depth_layers.h) are slices of one surface: they never hide each other.
    const double occlusion_px = std::max({0.5 * plan_layer.ellipse.semi_major_px, kOcclusionMinimumPx,
                                          kBlendSpanTolerances * settings.tolerance_px});
    layer.hides_up_to_vergence_dioptres = plan_layer.vergence_dioptres - occlusion_px / pixels_per_dioptre;
    // Kept only if some farther layer is far enough behind to be hidden by it.
    layer.occludes = index > 0 && layer.hides_up_to_vergence_dioptres > plan.layers.front().vergence_dioptres;
    const std::vector<RowSpan> box_spans = box_row_spans(spans, layer.box);
    const LayerConvolution method =
        plan_layer.blurred ? cheaper_layer_convolution(layer.box.x1 - layer.box.x0 + 1, layer.box.y1 - layer.box.y0 + 1,
                                                       box_spans, kernel, settings.vector_isa)
                           : LayerConvolution::direct;
    if (plan_layer.blurred) {
      ++counts.blurred_layers;
      ++(method == LayerConvolution::direct ? counts.direct_layers : counts.fft_layers);
    }
    if (method == LayerConvolution::direct) {
      direct[index] = direct_sum_kernel(kernel);
      layer.direct = &direct[index];
    } else {
      in_range &= blur_whole_layer_by_fft(image_cd_m2, buffers, static_cast<std::uint32_t>(index), layer.box, kernel,
                                          settings.threads, settings.vector_isa, buffers.fft_rows[index]);
      layer.blurred = &buffers.fft_rows[index];
    }
  }

  // The frame's sum (premultiplied RGB and coverage), divided in place tile by tile: stored only on
  // each row's written stretch (zero outside it), so a frame is not zero-filled first.
  result.width_px = width;
  result.height_px = height;
  result.rgba.resize(4 * static_cast<std::size_t>(width) * height);
  buffers.written.assign(static_cast<std::size_t>(height), RowSpan{});
  const TiledFrame frame{image_cd_m2, buffers.row_runs, layers, settings.vector_isa, result, buffers.written};
  // Tiles dealt to the threads in turn (tile t to chunk t mod chunks), so that the floor's heavy
  // rows and the wall's light ones are shared; each tile is composited alone, so the chunks and
  // their count change no value.
  const int tiles = (height + kDepthOfFieldTileRows - 1) / kDepthOfFieldTileRows;
  const int chunks = std::clamp(settings.threads, 1, tiles);
  if (buffers.tiles.size() < static_cast<std::size_t>(chunks)) buffers.tiles.resize(static_cast<std::size_t>(chunks));
  std::atomic<bool> tiles_in_range{true};
  parallel_indexed_chunks(chunks, chunks, [&](int chunk, int, int) {
    bool chunk_in_range = true;
    for (int tile = chunk; tile < tiles; tile += chunks) {
      const int y_first = tile * kDepthOfFieldTileRows;
      chunk_in_range &= composite_tile(frame, y_first, std::min(height, y_first + kDepthOfFieldTileRows),
                                       buffers.tiles[static_cast<std::size_t>(chunk)]);
    }
    if (!chunk_in_range) tiles_in_range = false;
  });
  if (!in_range || !tiles_in_range) refuse_pixels(image_cd_m2);
  result.depth = image_cd_m2.depth;
  if (report != nullptr) *report = counts;
}

}  // namespace glarelab
