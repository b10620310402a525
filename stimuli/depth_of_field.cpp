#include "stimuli/depth_of_field.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"
#include "stimuli/depth_of_field_blur.h"
#include "stimuli/depth_of_field_rows.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

struct Rectangle {
  int x0 = std::numeric_limits<int>::max(), y0 = std::numeric_limits<int>::max();
  int x1 = -1, y1 = -1;  // inclusive
};

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

Rectangle bounding_rectangle(const RowSpan* spans, int height) {
  Rectangle box;
  for (int y = 0; y < height; ++y) {
    if (spans[y].first >= spans[y].last) continue;
    box.x0 = std::min(box.x0, spans[y].first);
    box.x1 = std::max(box.x1, spans[y].last - 1);
    box.y0 = std::min(box.y0, y);
    box.y1 = std::max(box.y1, y);
  }
  return box;
}

// target = w x (r, g, b, 1) over `pixels` pixels of `source`: the source's alpha replaced by 1, whose
// product is w exactly (SSE2 where compiled: the same products a lane). Returns whether every
// source R, G and B lies in [0, FLT_MAX] (inspect_pixels' clean pixels), found on the loads the
// products make anyway: every pixel is read by its own layer, so the frame's check costs no pass.
bool weighted_pixels(float* __restrict target, const float* __restrict source, float weight, int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 colour_mask = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  const __m128 alpha_one = _mm_set_ps(1.0f, 0.0f, 0.0f, 0.0f);
  const __m128 w = _mm_set1_ps(weight);
  const __m128 zero = _mm_setzero_ps(), largest = _mm_set1_ps(std::numeric_limits<float>::max());
  __m128 in_range = _mm_castsi128_ps(_mm_set1_epi32(-1));
  for (int x = 0; x < pixels; ++x, target += 4, source += 4) {
    const __m128 value = _mm_or_ps(_mm_and_ps(_mm_loadu_ps(source), colour_mask), alpha_one);
    in_range = _mm_and_ps(in_range, _mm_and_ps(_mm_cmpge_ps(value, zero), _mm_cmple_ps(value, largest)));
    _mm_storeu_ps(target, _mm_mul_ps(w, value));
  }
  return _mm_movemask_ps(in_range) == 0xF;
#else
  bool in_range = true;
  for (int x = 0; x < pixels; ++x, target += 4, source += 4) {
    for (int c = 0; c < 3; ++c) {
      in_range = in_range && source[c] >= 0.0f && source[c] <= std::numeric_limits<float>::max();
      target[c] = weight * source[c];
    }
    target[3] = weight;
  }
  return in_range;
#endif
}

// The layer's pixels as premultiplied RGBA on their rows' segments in its bounding rectangle, a
// run of the plan at a time: on its own pixels colour and coverage times 1 - their blend weight, on
// the pixels blended into it from a neighbour times their blend weight, 0 between. A segment is a
// stretch of the layer's runs; a gap too short to part two (min_segment_gap_px) is kept as zeros.
// Returns whether every pixel read was in range (weighted_pixels).
bool fill_layer_rows(const ImageRGBA& image, const std::vector<std::vector<PixelRun>>& runs, std::uint32_t index,
                     const Rectangle& box, const EllipticalKernel& kernel, LayerRows& rows, int threads) {
  const int height = box.y1 - box.y0 + 1, gap = min_segment_gap_px(kernel);
  std::vector<std::size_t> row_first(static_cast<std::size_t>(height) + 1, 0);
  std::vector<RowSpan> segments;
  for (int y = 0; y < height; ++y) {
    const std::size_t row_start = segments.size();
    for (const PixelRun& run : runs[static_cast<std::size_t>(box.y0 + y)]) {
      if (run.own != index && run.blended != index) continue;
      const int first = run.first - box.x0, last = run.end - box.x0;
      if (segments.size() > row_start && first - segments.back().last < gap)
        segments.back().last = last;
      else
        segments.push_back({first, last});
    }
    row_first[static_cast<std::size_t>(y) + 1] = segments.size();
  }
  rows.lay_out_segments(box.x0, box.y0, box.x1 - box.x0 + 1, height, row_first, segments, kernel);
  std::atomic<bool> in_range{true};
  parallel_chunks(height, threads, [&](int first_row, int last_row) {
    bool chunk_in_range = true;
    for (int y = first_row; y < last_row; ++y) {
      const std::vector<PixelRun>& row_runs = runs[static_cast<std::size_t>(box.y0 + y)];
      auto run = row_runs.begin();
      for (std::size_t s = rows.first_segment[static_cast<std::size_t>(y)];
           s < rows.first_segment[static_cast<std::size_t>(y) + 1]; ++s) {
        const int frame_first = box.x0 + rows.segments[s].first, frame_last = box.x0 + rows.segments[s].last;
        float* target = rows.segment_pixels(s);
        while (run != row_runs.end() && run->end <= frame_first) ++run;
        for (; run != row_runs.end() && run->first < frame_last; ++run) {
          const int first = std::max(run->first, frame_first), last = std::min(run->end, frame_last);
          float* out = target + 4 * static_cast<std::size_t>(first - frame_first);
          if (run->own == index)
            chunk_in_range &= weighted_pixels(out, image.pixel(first, box.y0 + y), 1.0f - run->blend_weight, last - first);
          else if (run->blended == index)
            chunk_in_range &= weighted_pixels(out, image.pixel(first, box.y0 + y), run->blend_weight, last - first);
          else
            std::fill_n(out, 4 * static_cast<std::size_t>(last - first), 0.0f);
        }
        if (run != row_runs.begin()) --run;  // the last run may reach into the next segment
      }
    }
    if (!chunk_in_range) in_range = false;
  });
  return in_range;
}

// sum += transmission x the blurred layer (premultiplied colour and coverage alike) over `pixels`
// pixels, each product and sum rounded once (SSE2 where compiled: the same operations a lane).
void add_transmitted_row(float* __restrict sum, const float* __restrict transmission, const float* __restrict rgba,
                         int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4)
    _mm_storeu_ps(sum, _mm_add_ps(_mm_loadu_ps(sum), _mm_mul_ps(_mm_set1_ps(transmission[x]), _mm_loadu_ps(rgba))));
#else
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4) {
    const float t = transmission[x];
    for (int c = 0; c < 4; ++c) sum[c] += t * rgba[c];
  }
#endif
}

// sum = transmission x the blurred layer: the same bits as adding it to a zero sum (0 + p is p;
// p is never -0, the layers being non-negative).
void set_transmitted_row(float* __restrict sum, const float* __restrict transmission, const float* __restrict rgba,
                         int pixels) {
#if defined(__x86_64__) && defined(__GNUC__)
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4)
    _mm_storeu_ps(sum, _mm_mul_ps(_mm_set1_ps(transmission[x]), _mm_loadu_ps(rgba)));
#else
  for (int x = 0; x < pixels; ++x, sum += 4, rgba += 4) {
    const float t = transmission[x];
    for (int c = 0; c < 4; ++c) sum[c] = t * rgba[c];
  }
#endif
}

// The same where nothing hides the row yet (transmission 1: 1 x v is v, so the same bits).
void add_row(float* __restrict sum, const float* __restrict rgba, int pixels) {
  for (int k = 0; k < 4 * pixels; ++k) sum[k] += rgba[k];
}

// sum's row y on `clip` (frame columns) given the layer's blurred values there. `written` is the
// row's stretch that holds sums (outside it the sum is zero and not stored): the values are added
// inside it and written outside, the columns between it and `clip` zeroed, and it grows to hold
// both. transmission: the row's, or nullptr where nothing hides it yet.
void accumulate_row(float* sum_row, const float* transmission_row, RowSpan& written, const RowSpan& clip,
                    const float* rgba) {
  const auto put = [&](int first, int last, bool add) {
    if (first >= last) return;
    float* out = sum_row + 4 * static_cast<std::size_t>(first);
    const float* in = rgba + 4 * static_cast<std::size_t>(first - clip.first);
    if (transmission_row == nullptr) {
      if (add)
        add_row(out, in, last - first);
      else
        std::copy_n(in, 4 * static_cast<std::size_t>(last - first), out);
    } else if (add) {
      add_transmitted_row(out, transmission_row + first, in, last - first);
    } else {
      set_transmitted_row(out, transmission_row + first, in, last - first);
    }
  };
  if (written.first >= written.last) {
    put(clip.first, clip.last, false);
    written = clip;
    return;
  }
  // Zeros between the stretch and the clip, where they do not meet.
  if (clip.last < written.first)
    std::fill(sum_row + 4 * static_cast<std::size_t>(clip.last), sum_row + 4 * static_cast<std::size_t>(written.first), 0.0f);
  if (clip.first > written.last)
    std::fill(sum_row + 4 * static_cast<std::size_t>(written.last), sum_row + 4 * static_cast<std::size_t>(clip.first), 0.0f);
  put(clip.first, std::min(clip.last, written.first), false);
  put(std::max(clip.first, written.first), std::min(clip.last, written.last), true);
  put(std::max(clip.first, written.last), clip.last, false);
  written = {std::min(written.first, clip.first), std::max(written.last, clip.last)};
}

// A blurred layer's coverage (one float a pixel on its rows' spans inside the frame), kept until
// the first layer far enough behind it to be hidden by it.
struct PendingOccluder {
  double hides_up_to_vergence_dioptres;  // hides layers below this vergence
  int y0 = 0;                            // the frame row of spans[0]
  std::vector<RowSpan> spans;            // frame columns
  std::vector<std::size_t> offsets;      // each row's first value in coverage
  std::vector<float> coverage;
};

// Where a blurred layer (its rectangle at x0, y0; `spans` on it) lies in the frame: for each of its
// rows inside the frame, the span clipped to the frame's columns.
struct FramePlacement {
  int x0, y0, width_px, height_px;
  int first_row() const { return std::max(0, -y0); }
  int last_row(int rows) const { return std::min(rows, height_px - y0); }
  RowSpan clipped(const RowSpan& span) const {
    return {std::max(0, x0 + span.first), std::min(width_px, x0 + span.last)};
  }
};

// The occluder's rows laid out for the blurred spans of a layer placed at `place`.
PendingOccluder pending_occluder(double hides_up_to, const FramePlacement& place, const std::vector<RowSpan>& spans,
                                 std::vector<float> coverage_memory) {
  PendingOccluder occluder;
  occluder.coverage = std::move(coverage_memory);
  occluder.hides_up_to_vergence_dioptres = hides_up_to;
  const int first = place.first_row(), last = place.last_row(static_cast<int>(spans.size()));
  occluder.y0 = place.y0 + first;
  std::size_t size = 0;
  for (int row = first; row < last; ++row) {
    const RowSpan clip = place.clipped(spans[static_cast<std::size_t>(row)]);
    const bool empty = spans[static_cast<std::size_t>(row)].first >= spans[static_cast<std::size_t>(row)].last ||
                       clip.first >= clip.last;
    occluder.spans.push_back(empty ? RowSpan{} : clip);
    occluder.offsets.push_back(size);
    if (!empty) size += static_cast<std::size_t>(clip.last - clip.first);
  }
  occluder.coverage.resize(size);
  return occluder;
}

// t *= 1 - coverage over `count` pixels (SSE2 where compiled: the same operations a lane).
void transmit_through(float* __restrict t, const float* __restrict coverage, int count) {
  int x = 0;
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 one = _mm_set1_ps(1.0f);
  for (; x + 4 <= count; x += 4)
    _mm_storeu_ps(t + x, _mm_mul_ps(_mm_loadu_ps(t + x), _mm_sub_ps(one, _mm_loadu_ps(coverage + x))));
#endif
  for (; x < count; ++x) t[x] *= 1.0f - coverage[x];
}

// transmission *= 1 - the occluder's coverage; a row hidden for the first time is set to 1 first
// (`hidden`: the rows whose transmission is stored).
void occlude(std::vector<float>& transmission, std::vector<char>& hidden, int width_px, const PendingOccluder& occluder,
             int threads) {
  parallel_chunks(static_cast<int>(occluder.spans.size()), threads, [&](int first, int last) {
    for (int row = first; row < last; ++row) {
      const RowSpan& span = occluder.spans[static_cast<std::size_t>(row)];
      if (span.first >= span.last) continue;
      const std::size_t y = static_cast<std::size_t>(occluder.y0 + row);
      float* t_row = &transmission[y * width_px];
      if (!hidden[y]) {
        std::fill_n(t_row, width_px, 1.0f);
        hidden[y] = 1;
      }
      const float* coverage = occluder.coverage.data() + occluder.offsets[static_cast<std::size_t>(row)];
      transmit_through(t_row + span.first, coverage, span.last - span.first);
    }
  });
}

// The frame from the layers' sum (premultiplied, stored on each row's `written` stretch, zero
// outside): colour divided by coverage, alpha the input's.
void divide_by_coverage(const ImageRGBA& image_cd_m2, const std::vector<RowSpan>& written, int threads,
                        ImageRGBA& result) {
  const int width = result.width_px;
  parallel_chunks(result.height_px, threads, [&](int first, int last) {
    for (int y = first; y < last; ++y) {
      const RowSpan& stored = written[static_cast<std::size_t>(y)];
      for (int x = 0; x < width; ++x) {
        float* out = result.pixel(x, y);
        const float alpha = image_cd_m2.pixel(x, y)[3];
        if (x < stored.first || x >= stored.last) {
          // A zero sum: max(0 / 1, 0).
          out[0] = out[1] = out[2] = 0.0f;
          out[3] = alpha;
          continue;
        }
        // Every pixel belongs to a layer whose kernel keeps light at its centre, so coverage > 0.
        const float coverage = out[3] > 0.0f ? out[3] : 1.0f;
#if defined(__x86_64__) && defined(__GNUC__)
        // max(x, 0) as std::max(0, x) (0 for a NaN); each lane's quotient rounded once.
        _mm_storeu_ps(out, _mm_max_ps(_mm_div_ps(_mm_loadu_ps(out), _mm_set1_ps(coverage)), _mm_setzero_ps()));
#else
        for (int c = 0; c < 3; ++c) out[c] = std::max(0.0f, out[c] / coverage);
#endif
        out[3] = alpha;
      }
    }
  });
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
  // bad pixel is refused with its message once its layer is filled.
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

  DepthOfFieldReport counts;
  counts.layers = static_cast<int>(plan.layers.size());
  const double pixels_per_dioptre = geometry.pixels_per_dioptre();
  // The sum of the layers (premultiplied RGB and coverage), divided in place at the end: stored only
  // on each row's written stretch (zero outside it), so a frame is not zero-filled first.
  result.width_px = width;
  result.height_px = height;
  result.rgba.resize(4 * static_cast<std::size_t>(width) * height);
  std::vector<float>& sum = result.rgba;
  std::vector<RowSpan>& written = buffers.written;
  written.assign(static_cast<std::size_t>(height), RowSpan{});
  // The nearer layers' transmission, stored only for the rows some layer hides (1 elsewhere).
  std::vector<float>& transmission = buffers.transmission;
  transmission.resize(static_cast<std::size_t>(width) * height);
  std::vector<char>& hidden = buffers.hidden_rows;
  hidden.assign(static_cast<std::size_t>(height), 0);
  std::vector<PendingOccluder> pending;
  // Each layer's kernel (a layer within its pixel passes through: the identity kernel's sum is each
  // value itself), and its rows' buffer kept from layer to layer, made once as large as the largest.
  std::vector<EllipticalKernel> kernels;
  LayerRows& rows = buffers.rows;
  std::size_t largest_floats = 0;
  for (std::size_t index = 0; index < plan.layers.size(); ++index) {
    kernels.push_back(plan.layers[index].blurred ? elliptical_kernel(plan.layers[index].ellipse)
                                                 : EllipticalKernel{0, 0, {1.0}, 1.0});
    const std::size_t pad = 2 * static_cast<std::size_t>(2 * kernels.back().radius_x_px + kDirectBlockPx);
    std::size_t floats = 0;
    for (int y = 0; y < height; ++y) {
      const RowSpan& span = frame_spans[index * static_cast<std::size_t>(height) + static_cast<std::size_t>(y)];
      if (span.first < span.last) floats += 4 * (static_cast<std::size_t>(span.last - span.first) + pad);
    }
    largest_floats = std::max(largest_floats, floats);
  }
  rows.reserve(largest_floats);
  // Near to far (plan.layers ascends in vergence): each layer's light is added through the
  // transmission of the nearer layers that hide it (see kOcclusionMinimumPx in the header).
  for (std::size_t index = plan.layers.size(); index-- > 0;) {
    const DepthLayer& layer = plan.layers[index];
    counts.max_blur_error_px = std::max(counts.max_blur_error_px, layer.max_blur_error_px);
    for (auto occluder = pending.begin(); occluder != pending.end();) {
      if (occluder->hides_up_to_vergence_dioptres > layer.vergence_dioptres) {
        occlude(transmission, hidden, width, *occluder, settings.threads);
        buffers.coverages.push_back(std::move(occluder->coverage));
        occluder = pending.erase(occluder);
      } else {
        ++occluder;
      }
    }
    const RowSpan* spans = &frame_spans[index * static_cast<std::size_t>(height)];
    const Rectangle box = bounding_rectangle(spans, height);
    if (box.x1 < 0) continue;  // no pixel (a layer is made only for depths the scene has)
    const EllipticalKernel& kernel = kernels[index];
    if (!fill_layer_rows(image_cd_m2, buffers.row_runs, static_cast<std::uint32_t>(index), box, kernel, rows,
                         settings.threads))
      refuse_pixels(image_cd_m2);
    const std::vector<RowSpan> blurred_spans = blurred_row_spans(rows.spans, kernel);
    const FramePlacement place{box.x0 - kernel.radius_x_px, box.y0 - kernel.radius_y_px, width, height};

    // Layers that blend (depth_layers.h) are slices of one surface: they never hide each other.
    const double occlusion_px = std::max(
        {0.5 * layer.ellipse.semi_major_px, kOcclusionMinimumPx, kBlendSpanTolerances * settings.tolerance_px});
    const double hides_up_to = layer.vergence_dioptres - occlusion_px / pixels_per_dioptre;
    // Kept only if some farther layer is far enough behind to be hidden by it.
    const bool occludes = index > 0 && hides_up_to > plan.layers.front().vergence_dioptres;
    PendingOccluder occluder;
    if (occludes) {
      std::vector<float> memory;
      if (!buffers.coverages.empty()) {
        memory = std::move(buffers.coverages.back());
        buffers.coverages.pop_back();
      }
      occluder = pending_occluder(hides_up_to, place, blurred_spans, std::move(memory));
    }

    // sum += transmission x blurred row inside the frame; the occluder keeps the row's coverage.
    const BlurredRowSink add_row = [&](int row, int first, int count, const float* rgba) {
      const int y = place.y0 + row;
      if (y < 0 || y >= height) return;
      const RowSpan clip = place.clipped({first, first + count});
      if (clip.first >= clip.last) return;
      const std::size_t row_start = static_cast<std::size_t>(y) * width;
      const float* in = rgba + 4 * static_cast<std::size_t>(clip.first - place.x0 - first);
      accumulate_row(&sum[4 * row_start], hidden[static_cast<std::size_t>(y)] ? &transmission[row_start] : nullptr,
                     written[static_cast<std::size_t>(y)], clip, in);
#if defined(__x86_64__) && defined(__GNUC__)
      // The next row's sum on about the same columns, asked for now: its read waits on memory
      // otherwise (a row is too short a stream for the hardware's prefetcher), and the blur of the
      // next row runs meanwhile.
      if (y + 1 < height) {
        const char* next = reinterpret_cast<const char*>(&sum[4 * (row_start + width + clip.first)]);
        const char* end = reinterpret_cast<const char*>(&sum[4 * (row_start + width + clip.last)]);
        for (; next < end; next += 64) _mm_prefetch(next, _MM_HINT_T1);
      }
#endif
      if (occludes) {
        float* coverage = occluder.coverage.data() + occluder.offsets[static_cast<std::size_t>(y - occluder.y0)];
        for (int x = 0; x < clip.last - clip.first; ++x) coverage[x] = in[4 * static_cast<std::size_t>(x) + 3];
      }
    };
    const LayerConvolution method = layer.blurred
                                        ? cheaper_layer_convolution(rows.width_px, rows.height_px, rows.spans, kernel)
                                        : LayerConvolution::direct;
    if (layer.blurred) {
      ++counts.blurred_layers;
      ++(method == LayerConvolution::direct ? counts.direct_layers : counts.fft_layers);
    }
    if (method == LayerConvolution::direct) {
      blur_rows_direct(rows, kernel, settings.threads, settings.vector_isa, add_row);
    } else {
      blur_rows_fft(rows, kernel, settings.threads, add_row, buffers.fft);
    }
    if (occludes) pending.push_back(std::move(occluder));
  }
  for (PendingOccluder& occluder : pending) buffers.coverages.push_back(std::move(occluder.coverage));

  divide_by_coverage(image_cd_m2, written, settings.threads, result);
  result.depth = image_cd_m2.depth;
  if (report != nullptr) *report = counts;
}

}  // namespace glarelab
