#include "stimuli/depth_of_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/parallel_for.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

struct Rectangle {
  int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max();
  int x1 = -1, y1 = -1;  // inclusive
};

// The layer's pixels as premultiplied RGBA on their bounding rectangle: on its own pixels colour
// and coverage times 1 - their blend weight, on the pixels blended into it from a neighbour times
// their blend weight, 0 elsewhere; `spans` gets each row's span of those pixels.
LayerImage layer_image(const ImageRGBA& image, const DepthLayerPlan& plan, std::uint32_t index, const Rectangle& box,
                       std::vector<RowSpan>& spans, int threads) {
  LayerImage layer;
  layer.x0_px = box.x0;
  layer.y0_px = box.y0;
  layer.width_px = box.x1 - box.x0 + 1;
  layer.height_px = box.y1 - box.y0 + 1;
  layer.rgba.assign(4 * static_cast<std::size_t>(layer.width_px) * layer.height_px, 0.0f);
  spans.assign(static_cast<std::size_t>(layer.height_px), RowSpan{});
  parallel_chunks(layer.height_px, threads, [&](int first_row, int last_row) {
    for (int y = first_row; y < last_row; ++y) {
      const std::size_t row_start = static_cast<std::size_t>(box.y0 + y) * image.width_px + box.x0;
      RowSpan span{layer.width_px, 0};
      for (int x = 0; x < layer.width_px; ++x) {
        const std::size_t k = row_start + static_cast<std::size_t>(x);
        const bool own = plan.layer_of_pixel[k] == index, blended = plan.blend_layer_of_pixel[k] == index;
        if (!own && !blended) continue;
        const float weight = own ? 1.0f - plan.blend_weight[k] : plan.blend_weight[k];
        const float* source = image.pixel(box.x0 + x, box.y0 + y);
        float* target = layer.pixel(x, y);
        target[0] = weight * source[0];
        target[1] = weight * source[1];
        target[2] = weight * source[2];
        target[3] = weight;
        span.first = std::min(span.first, x);
        span.last = x + 1;
      }
      if (span.first < span.last) spans[static_cast<std::size_t>(y)] = span;
    }
  });
  return layer;
}

// The rectangle of a layer that lies inside the frame, as [x_first, x_last) x [y_first, y_last).
struct Clip {
  int x_first, x_last, y_first, y_last;
  bool empty() const { return x_first >= x_last || y_first >= y_last; }
};
Clip clip_to_frame(const LayerImage& layer, int width_px, int height_px) {
  return {std::max(0, layer.x0_px), std::min(width_px, layer.x0_px + layer.width_px), std::max(0, layer.y0_px),
          std::min(height_px, layer.y0_px + layer.height_px)};
}

// sum += transmission x layer (premultiplied colour and coverage alike) inside the frame, on the
// layer's nonzero spans.
void add_transmitted(std::vector<float>& sum, const std::vector<float>& transmission, int width_px, int height_px,
                     const LayerImage& layer, const std::vector<RowSpan>& spans, int threads) {
  const Clip clip = clip_to_frame(layer, width_px, height_px);
  if (clip.empty()) return;
  parallel_chunks(clip.y_last - clip.y_first, threads, [&](int first, int last) {
    for (int y = clip.y_first + first; y < clip.y_first + last; ++y) {
      const RowSpan& span = spans[static_cast<std::size_t>(y - layer.y0_px)];
      const int x_first = std::max(clip.x_first, layer.x0_px + span.first);
      const int x_last = std::min(clip.x_last, layer.x0_px + span.last);
      for (int x = x_first; x < x_last; ++x) {
        const std::size_t k = static_cast<std::size_t>(y) * width_px + x;
        const float t = transmission[k];
        const float* in = layer.pixel(x - layer.x0_px, y - layer.y0_px);
        float* out = &sum[4 * k];
        for (int c = 0; c < 4; ++c) out[c] += t * in[c];
      }
    }
  });
}

// A blurred layer's coverage (one float a pixel, on its rectangle and spans), kept until the first
// layer far enough behind it to be hidden by it.
struct PendingOccluder {
  double hides_up_to_vergence_dioptres;  // hides layers below this vergence
  LayerImage coverage;
  std::vector<RowSpan> spans;
};

LayerImage coverage_of(const LayerImage& layer, int threads) {
  LayerImage coverage;
  coverage.x0_px = layer.x0_px;
  coverage.y0_px = layer.y0_px;
  coverage.width_px = layer.width_px;
  coverage.height_px = layer.height_px;
  coverage.rgba.resize(static_cast<std::size_t>(layer.width_px) * layer.height_px);
  parallel_chunks(layer.height_px, threads, [&](int first, int last) {
    for (std::size_t k = static_cast<std::size_t>(first) * layer.width_px;
         k < static_cast<std::size_t>(last) * layer.width_px; ++k)
      coverage.rgba[k] = layer.rgba[4 * k + 3];
  });
  return coverage;
}

// transmission *= 1 - the occluder's coverage.
void occlude(std::vector<float>& transmission, int width_px, int height_px, const PendingOccluder& occluder,
             int threads) {
  const LayerImage& coverage = occluder.coverage;
  const Clip clip = clip_to_frame(coverage, width_px, height_px);
  if (clip.empty()) return;
  parallel_chunks(clip.y_last - clip.y_first, threads, [&](int first, int last) {
    for (int y = clip.y_first + first; y < clip.y_first + last; ++y) {
      const RowSpan& span = occluder.spans[static_cast<std::size_t>(y - coverage.y0_px)];
      const int x_first = std::max(clip.x_first, coverage.x0_px + span.first);
      const int x_last = std::min(clip.x_last, coverage.x0_px + span.last);
      const float* row = &coverage.rgba[static_cast<std::size_t>(y - coverage.y0_px) * coverage.width_px];
      for (int x = x_first; x < x_last; ++x)
        transmission[static_cast<std::size_t>(y) * width_px + x] *= 1.0f - row[x - coverage.x0_px];
    }
  });
}

void refuse(const std::string& what) { throw std::invalid_argument("stimuli/depth_of_field: " + what); }

}  // namespace

void check_depth_of_field_inputs(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                                 const DepthOfFieldSettings& settings) {
  if (image_cd_m2.empty()) refuse("the image is empty");
  if (!(settings.degrees_per_pixel > 0.0) || !std::isfinite(settings.degrees_per_pixel))
    refuse("degrees per pixel " + std::to_string(settings.degrees_per_pixel) + " must be positive and finite");
  if (!(settings.pupil_radius_m > 0.0) || !std::isfinite(settings.pupil_radius_m))
    refuse("the pupil radius " + std::to_string(settings.pupil_radius_m) + " m must be positive and finite");
  if (!(settings.tolerance_px > 0.0) || !std::isfinite(settings.tolerance_px))
    refuse("the layer tolerance " + std::to_string(settings.tolerance_px) + " px must be positive and finite");
  if (settings.threads < 1) refuse("threads " + std::to_string(settings.threads) + " must be at least 1");
  if (!settings.residual_error) refuse("no eye error function was given");
  const NonFiniteReport pixels = inspect_pixels(image_cd_m2);
  if (!pixels.clean()) refuse("the image has " + pixels.describe() + "; luminances must be finite and non-negative");
  check_scene_depth(depth_m, image_cd_m2.width_px, image_cd_m2.height_px, "the depth map");
}

ImageRGBA apply_depth_of_field(const ImageRGBA& image_cd_m2, const std::vector<float>& depth_m,
                               const DepthOfFieldSettings& settings, DepthOfFieldReport* report) {
  check_depth_of_field_inputs(image_cd_m2, depth_m, settings);
  const int width = image_cd_m2.width_px, height = image_cd_m2.height_px;
  const BlurGeometry geometry{settings.degrees_per_pixel, settings.pupil_radius_m};
  const DepthLayerPlan plan =
      plan_depth_layers(depth_m, geometry, settings.residual_error, settings.tolerance_px, settings.threads);

  std::vector<Rectangle> boxes(plan.layers.size());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * width + x;
      for (std::uint32_t index : {plan.layer_of_pixel[k], plan.blend_layer_of_pixel[k]}) {
        Rectangle& box = boxes[index];
        box.x0 = std::min(box.x0, x);
        box.x1 = std::max(box.x1, x);
        box.y0 = std::min(box.y0, y);
        box.y1 = std::max(box.y1, y);
      }
    }

  DepthOfFieldReport counts;
  counts.layers = static_cast<int>(plan.layers.size());
  const double pixels_per_dioptre = geometry.pixels_per_dioptre();
  std::vector<float> sum(4 * static_cast<std::size_t>(width) * height, 0.0f);  // premultiplied RGB, coverage
  std::vector<float> transmission(static_cast<std::size_t>(width) * height, 1.0f);
  std::vector<PendingOccluder> pending;
  // Near to far (plan.layers ascends in vergence): each layer's light is added through the
  // transmission of the nearer layers that hide it (see kOcclusionMinimumPx in the header).
  for (std::size_t index = plan.layers.size(); index-- > 0;) {
    const DepthLayer& layer = plan.layers[index];
    counts.max_blur_error_px = std::max(counts.max_blur_error_px, layer.max_blur_error_px);
    for (auto occluder = pending.begin(); occluder != pending.end();) {
      if (occluder->hides_up_to_vergence_dioptres > layer.vergence_dioptres) {
        occlude(transmission, width, height, *occluder, settings.threads);
        occluder = pending.erase(occluder);
      } else {
        ++occluder;
      }
    }
    std::vector<RowSpan> spans;
    LayerImage pixels =
        layer_image(image_cd_m2, plan, static_cast<std::uint32_t>(index), boxes[index], spans, settings.threads);
    if (layer.blurred) {
      const EllipticalKernel kernel = elliptical_kernel(layer.ellipse);
      const LayerConvolution method = cheaper_layer_convolution(pixels, spans, kernel);
      ++counts.blurred_layers;
      ++(method == LayerConvolution::direct ? counts.direct_layers : counts.fft_layers);
      pixels = blur_layer(pixels, spans, kernel, method, settings.threads, settings.vector_isa);
      spans = blurred_row_spans(spans, kernel);
    }
    add_transmitted(sum, transmission, width, height, pixels, spans, settings.threads);
    // Layers that blend (depth_layers.h) are slices of one surface: they never hide each other.
    const double occlusion_px = std::max(
        {0.5 * layer.ellipse.semi_major_px, kOcclusionMinimumPx, kBlendSpanTolerances * settings.tolerance_px});
    const double hides_up_to = layer.vergence_dioptres - occlusion_px / pixels_per_dioptre;
    // Kept only if some farther layer is far enough behind to be hidden by it.
    if (index > 0 && hides_up_to > plan.layers.front().vergence_dioptres)
      pending.push_back({hides_up_to, coverage_of(pixels, settings.threads), std::move(spans)});
  }

  ImageRGBA result = image_cd_m2;
  parallel_chunks(height, settings.threads, [&](int first, int last) {
    for (int y = first; y < last; ++y)
      for (int x = 0; x < width; ++x) {
        const float* in = &sum[4 * (static_cast<std::size_t>(y) * width + x)];
        float* out = result.pixel(x, y);
        // Every pixel belongs to a layer whose kernel keeps light at its centre, so coverage > 0.
        const float coverage = in[3] > 0.0f ? in[3] : 1.0f;
        for (int c = 0; c < 3; ++c) out[c] = std::max(0.0f, in[c] / coverage);
      }
  });
  if (report != nullptr) *report = counts;
  return result;
}

}  // namespace glarelab
