#include "stimuli/depth_layers.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "core/parallel_for.h"
#include "stimuli/scene_depth.h"

namespace glarelab {
namespace {

// 1 / vergence, with vergence 0 at infinity.
double distance_for_vergence_m(double vergence) { return vergence == 0.0 ? INFINITY : 1.0 / vergence; }

// The depths of the map's runs of equal depth (a plane, a row of a floor), as 32-bit patterns.
std::vector<std::uint32_t> run_depth_keys(const std::vector<float>& depth_m) {
  std::vector<std::uint32_t> keys;
  for (std::size_t k = 0; k < depth_m.size(); ++k)
    if (k == 0 || depth_m[k] != depth_m[k - 1]) keys.push_back(std::bit_cast<std::uint32_t>(depth_m[k]));
  return keys;
}

// The distinct depths among `keys` (positive depths' patterns), ascending. Positive floats (and
// +inf) order as their 32-bit patterns do, so a least-significant-byte-first radix sort of the
// patterns sorts them in four linear passes (a comparison sort of a rendered depth map, every pixel
// its own depth, took most of the stage's bookkeeping time).
std::vector<float> distinct_depths_m(std::vector<std::uint32_t> keys) {
  std::vector<std::uint32_t> sorted(keys.size());
  for (int shift = 0; shift < 32; shift += 8) {
    std::array<std::size_t, 257> start{};
    for (std::uint32_t key : keys) ++start[((key >> shift) & 0xffu) + 1];
    if (std::any_of(start.begin() + 1, start.end(), [&](std::size_t n) { return n == keys.size(); })) continue;
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    for (std::uint32_t key : keys) sorted[start[(key >> shift) & 0xffu]++] = key;
    keys.swap(sorted);
  }
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<float> depths(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) depths[k] = std::bit_cast<float>(keys[k]);
  return depths;
}

DioptricPower checked_error(const EyeErrorAtDistance& error, double distance_m) {
  const DioptricPower power = error(distance_m);
  if (!std::isfinite(power.xx()) || !std::isfinite(power.xy()) || !std::isfinite(power.yy()) ||
      !std::isfinite(power.matrix_dioptres[0][1]))
    throw std::invalid_argument("stimuli/depth_layers: the eye's power error for a point at " +
                                std::to_string(distance_m) + " m is not finite");
  return power;
}

}  // namespace

double BlurGeometry::pixels_per_dioptre() const {
  return pupil_radius_m / (degrees_per_pixel * std::numbers::pi / 180.0);
}

double blur_error_px(const DioptricPower& first, const DioptricPower& second, const BlurGeometry& geometry) {
  const PrincipalPowers difference = principal_powers(first - second);
  return std::max(std::abs(difference.p1_dioptres), std::abs(difference.p2_dioptres)) * geometry.pixels_per_dioptre();
}

DepthLayerPlan plan_depth_layers(const std::vector<float>& depth_m, const BlurGeometry& geometry,
                                 const EyeErrorAtDistance& error, double tolerance_px, int threads) {
  DepthLayerPlan plan;
  plan_depth_layers(depth_m, geometry, error, tolerance_px, threads, plan);
  return plan;
}

namespace {

// A depth's layer, blend layer and blend weight, the same for every pixel of that depth.
struct LayerAssignment {
  std::uint32_t own = 0, other = 0;
  float weight = 0.0f;
};

// The plan's layers made from the scene's depths, and each depth's assignment to them.
class LayerAssigner {
 public:
  LayerAssigner(const std::vector<DepthLayer>& layers, std::vector<bool> blends_with_next)
      : layers_(layers), blends_with_next_(std::move(blends_with_next)) {
    for (const DepthLayer& layer : layers) near_bounds_.push_back(layer.near_vergence_dioptres);
  }
  // Blending with the neighbouring layer on the side of the depth's vergence from its layer's middle.
  LayerAssignment operator()(float depth_m) const {
    const double v = vergence_dioptres(depth_m);
    LayerAssignment a;
    a.own = static_cast<std::uint32_t>(std::lower_bound(near_bounds_.begin(), near_bounds_.end(), v) -
                                       near_bounds_.begin());
    const double middle = layers_[a.own].vergence_dioptres;
    a.other = a.own;
    if (v > middle && a.own + 1 < layers_.size() && blends_with_next_[a.own]) a.other = a.own + 1;
    if (v < middle && a.own > 0 && blends_with_next_[a.own - 1]) a.other = a.own - 1;
    a.weight = a.other == a.own ? 0.0f : static_cast<float>((v - middle) / (layers_[a.other].vergence_dioptres - middle));
    return a;
  }

 private:
  const std::vector<DepthLayer>& layers_;
  std::vector<bool> blends_with_next_;
  std::vector<double> near_bounds_;
};

// The plan's settings, refused as the callers' contracts say (std::invalid_argument).
void check_plan_settings(const BlurGeometry& geometry, const EyeErrorAtDistance& error, double tolerance_px) {
  if (!(geometry.degrees_per_pixel > 0.0) || !std::isfinite(geometry.degrees_per_pixel) ||
      !(geometry.pupil_radius_m > 0.0) || !std::isfinite(geometry.pupil_radius_m))
    throw std::invalid_argument("stimuli/depth_layers: degrees per pixel (" +
                                std::to_string(geometry.degrees_per_pixel) + ") and pupil radius (" +
                                std::to_string(geometry.pupil_radius_m) + " m) must be positive and finite");
  if (!(tolerance_px > 0.0) || !std::isfinite(tolerance_px))
    throw std::invalid_argument("stimuli/depth_layers: the layer tolerance " + std::to_string(tolerance_px) +
                                " px must be positive and finite");
  if (!error) throw std::invalid_argument("stimuli/depth_layers: no eye error function was given");
}

[[noreturn]] void refuse_depth(float depth_m, std::size_t index) {
  throw std::invalid_argument("stimuli/depth_layers: depth " + std::to_string(depth_m) + " m at index " +
                              std::to_string(index) + " is not a positive distance (stimuli/scene_depth.h checks maps)");
}

// plan.layers for the scene's depths (`keys`: run_depth_keys of a checked map, or any list
// holding each of its depths), and the assigner of depths to them.
LayerAssigner plan_layers(std::vector<std::uint32_t> keys, const BlurGeometry& geometry, const EyeErrorAtDistance& error,
                          double tolerance_px, DepthLayerPlan& plan) {
  // The distinct vergences of the scene, ascending (far to near): the distinct depths descending.
  const std::vector<float> depths = distinct_depths_m(std::move(keys));
  std::vector<double> vergences(depths.size());
  for (std::size_t k = 0; k < depths.size(); ++k) vergences[k] = vergence_dioptres(depths[depths.size() - 1 - k]);

  std::vector<DioptricPower> errors;
  errors.reserve(vergences.size());
  for (double v : vergences) errors.push_back(checked_error(error, distance_for_vergence_m(v)));

  plan.layers.clear();
  for (std::size_t first = 0; first < vergences.size();) {
    std::size_t end = first + 1;
    while (end < vergences.size() && blur_error_px(errors[end], errors[first], geometry) <= 2.0 * tolerance_px) ++end;
    DepthLayer layer;
    layer.far_vergence_dioptres = vergences[first];
    layer.near_vergence_dioptres = vergences[end - 1];
    layer.vergence_dioptres = 0.5 * (layer.far_vergence_dioptres + layer.near_vergence_dioptres);
    const DioptricPower middle = checked_error(error, distance_for_vergence_m(layer.vergence_dioptres));
    layer.ellipse = pixel_blur_ellipse(middle, geometry.pupil_radius_m, geometry.degrees_per_pixel);
    for (std::size_t k = first; k < end; ++k)
      layer.max_blur_error_px = std::max(layer.max_blur_error_px, blur_error_px(errors[k], middle, geometry));
    layer.blurred = layer.ellipse.semi_major_px > tolerance_px;
    layer.error = middle;
    plan.layers.push_back(layer);
    first = end;
  }

  // Blending with the neighbouring layer on the side of the pixel's vergence from its layer's middle.
  std::vector<bool> blends_with_next(plan.layers.size(), false);
  for (std::size_t i = 0; i + 1 < plan.layers.size(); ++i)
    blends_with_next[i] =
        blur_error_px(plan.layers[i].error, plan.layers[i + 1].error, geometry) <= kBlendSpanTolerances * tolerance_px;
  return LayerAssigner(plan.layers, std::move(blends_with_next));
}

}  // namespace

void plan_depth_layers(const std::vector<float>& depth_m, const BlurGeometry& geometry, const EyeErrorAtDistance& error,
                       double tolerance_px, int threads, DepthLayerPlan& plan) {
  check_plan_settings(geometry, error, tolerance_px);
  if (!all_depths_positive(depth_m))
    for (std::size_t k = 0; k < depth_m.size(); ++k)
      if (!(depth_m[k] > 0.0f)) refuse_depth(depth_m[k], k);
  const LayerAssigner assign = plan_layers(run_depth_keys(depth_m), geometry, error, tolerance_px, plan);
  // Each pixel to the layer whose vergence range holds it, and its blend, in one pass in chunks;
  // a run of equal depths (a plane, a row of a floor) takes the values of its first pixel.
  plan.layer_of_pixel.resize(depth_m.size());
  plan.blend_layer_of_pixel.resize(depth_m.size());
  plan.blend_weight.resize(depth_m.size());
  const int chunks = std::max(1, threads);
  std::vector<std::vector<std::size_t>> counts(static_cast<std::size_t>(chunks),
                                               std::vector<std::size_t>(plan.layers.size(), 0));
  parallel_indexed_chunks(static_cast<int>(depth_m.size()), chunks, [&](int chunk, int begin, int stop) {
    std::vector<std::size_t>& count = counts[static_cast<std::size_t>(chunk)];
    float last_depth = 0.0f;  // no depth is 0 (checked above)
    LayerAssignment a;
    for (int k = begin; k < stop; ++k) {
      const std::size_t pixel = static_cast<std::size_t>(k);
      if (depth_m[pixel] != last_depth) {
        last_depth = depth_m[pixel];
        a = assign(last_depth);
      }
      plan.layer_of_pixel[pixel] = a.own;
      plan.blend_layer_of_pixel[pixel] = a.other;
      plan.blend_weight[pixel] = a.weight;
      ++count[a.own];
    }
  });
  for (const std::vector<std::size_t>& count : counts)
    for (std::size_t i = 0; i < plan.layers.size(); ++i) plan.layers[i].pixel_count += count[i];
}

namespace {

// The end of the run of depths equal to depth[x] (ordered equality: a NaN is a run of its own),
// eight depths a step with SSE2 where compiled: the scalar loop, a compare and a branch a pixel,
// was most of the plan's time on frames whose rows are long runs.
int run_end(const float* depth, int x, int width_px) {
  int end = x + 1;
#if defined(__x86_64__) && defined(__GNUC__)
  const __m128 value = _mm_set1_ps(depth[x]);
  for (; end + 8 <= width_px; end += 8) {
    const int equal = _mm_movemask_ps(_mm_cmpeq_ps(_mm_loadu_ps(depth + end), value)) |
                      (_mm_movemask_ps(_mm_cmpeq_ps(_mm_loadu_ps(depth + end + 4), value)) << 4);
    if (equal != 0xFF) return end + std::countr_one(static_cast<unsigned>(equal));
  }
#endif
  while (end < width_px && depth[end] == depth[x]) ++end;
  return end;
}

}  // namespace

void plan_depth_layer_runs(const std::vector<float>& depth_m, int width_px, int height_px, const BlurGeometry& geometry,
                           const EyeErrorAtDistance& error, double tolerance_px, int threads, DepthLayerPlan& plan,
                           std::vector<std::vector<PixelRun>>& runs) {
  if (width_px <= 0 || height_px <= 0 ||
      depth_m.size() != static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px))
    throw std::invalid_argument("stimuli/depth_layers: " + std::to_string(depth_m.size()) + " depths for a " +
                                std::to_string(width_px) + " x " + std::to_string(height_px) + " px frame");
  check_plan_settings(geometry, error, tolerance_px);
  plan.layer_of_pixel.clear();
  plan.blend_layer_of_pixel.clear();
  plan.blend_weight.clear();
  runs.resize(static_cast<std::size_t>(height_px));
  const int chunks = std::max(1, std::min(threads, height_px));
  // Each row's runs of equal depth, the depth held in blend_weight until the layers are known,
  // and whether each is a positive distance: the only pass over the depths.
  std::atomic<bool> all_positive{true};
  parallel_chunks(height_px, chunks, [&](int first_row, int last_row) {
    bool positive = true;
    for (int y = first_row; y < last_row; ++y) {
      const float* depth = depth_m.data() + static_cast<std::size_t>(y) * width_px;
      std::vector<PixelRun>& row_runs = runs[static_cast<std::size_t>(y)];
      row_runs.clear();
      for (int x = 0; x < width_px;) {
        const int end = run_end(depth, x, width_px);
        positive = positive && depth[x] > 0.0f;  // a NaN is a run of its own
        row_runs.push_back({x, end, 0, 0, depth[x]});
        x = end;
      }
    }
    if (!positive) all_positive = false;
  });
  std::vector<std::uint32_t> keys;
  for (const std::vector<PixelRun>& row_runs : runs)
    for (const PixelRun& run : row_runs) {
      if (!all_positive && !(run.blend_weight > 0.0f))
        refuse_depth(run.blend_weight, static_cast<std::size_t>(&row_runs - runs.data()) * width_px + run.first);
      keys.push_back(std::bit_cast<std::uint32_t>(run.blend_weight));
    }
  const LayerAssigner assign = plan_layers(std::move(keys), geometry, error, tolerance_px, plan);
  std::vector<std::vector<std::size_t>> counts(static_cast<std::size_t>(chunks),
                                               std::vector<std::size_t>(plan.layers.size(), 0));
  // Each run its depth's values (as above); a run with the values of the one before it joins it.
  parallel_indexed_chunks(height_px, chunks, [&](int chunk, int first_row, int last_row) {
    std::vector<std::size_t>& count = counts[static_cast<std::size_t>(chunk)];
    for (int y = first_row; y < last_row; ++y) {
      std::vector<PixelRun>& row_runs = runs[static_cast<std::size_t>(y)];
      std::size_t kept = 0;
      for (std::size_t r = 0; r < row_runs.size(); ++r) {
        const PixelRun run = row_runs[r];
        const LayerAssignment a = assign(run.blend_weight);
        count[a.own] += static_cast<std::size_t>(run.end - run.first);
        if (kept > 0 && row_runs[kept - 1].own == a.own && row_runs[kept - 1].blended == a.other &&
            row_runs[kept - 1].blend_weight == a.weight)
          row_runs[kept - 1].end = run.end;
        else
          row_runs[kept++] = {run.first, run.end, a.own, a.other, a.weight};
      }
      row_runs.resize(kept);
    }
  });
  for (const std::vector<std::size_t>& count : counts)
    for (std::size_t i = 0; i < plan.layers.size(); ++i) plan.layers[i].pixel_count += count[i];
}

}  // namespace glarelab
