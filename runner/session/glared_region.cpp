// Glared frames kept as their changed rectangle, exact or at half precision
// (runner/session/glared_region.h).
#include "runner/session/glared_region.h"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <utility>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "core/half_float.h"
#include "core/image_token.h"

namespace glarelab {
namespace {

// The half-precision frames of an interval are freed together when it ends, while the next
// trial's are being kept (29 of 3 MB for a 1024 x 512 frame, 12 MB at 1920 x 1080). Allocated
// afresh, each was zeroed by the vector and then faulted in page by page by the kernel: in the
// demo, half of the session's page faults and a fifth of its CPU time. Storage handed back is
// reused as it is (resizing to the same size writes nothing), up to a bound on what is held idle.
class HalfStoragePool {
 public:
  // Never destroyed: a region may be freed while the process exits.
  static HalfStoragePool& instance() {
    static auto* const pool = new HalfStoragePool;
    return *pool;
  }

  std::vector<std::uint16_t> take(std::size_t values) {
    std::vector<std::uint16_t> storage, too_small;
    {
      const std::lock_guard lock(mutex_);
      // The idle storage whose capacity fits best: equal sizes are the rule (one frame's region
      // after another's), and among equals the one freed last (its memory the warmest in the
      // caches). When none holds enough, the smallest is let go (frames of another size came
      // before), so storage of sizes no longer asked for does not stay.
      std::size_t best = idle_.size(), smallest = idle_.size();
      for (std::size_t i = 0; i < idle_.size(); ++i) {
        const std::size_t capacity = idle_[i].capacity();
        if (capacity >= values && (best == idle_.size() || capacity <= idle_[best].capacity())) best = i;
        if (smallest == idle_.size() || capacity < idle_[smallest].capacity()) smallest = i;
      }
      const bool fits = best < idle_.size();
      const std::size_t chosen = fits ? best : smallest;
      if (chosen < idle_.size()) {
        std::vector<std::uint16_t>& taken = fits ? storage : too_small;
        taken = std::move(idle_[chosen]);
        idle_[chosen] = std::move(idle_.back());
        idle_.pop_back();
        idle_bytes_ -= taken.capacity() * sizeof(std::uint16_t);
      }
    }  // too_small is freed here, outside the lock
    storage.resize(values);  // every value is written by the caller
    return storage;
  }

  // Storages of `values` halves until the idle ones reach the bound.
  void fill(std::size_t values) {
    const std::size_t bytes = values * sizeof(std::uint16_t);
    if (bytes == 0) return;
    for (;;) {
      {
        const std::lock_guard lock(mutex_);
        if (idle_bytes_ + bytes > kIdleBytes) return;
      }
      give(std::vector<std::uint16_t>(values));
    }
  }

  void give(std::vector<std::uint16_t>&& storage) {
    const std::size_t bytes = storage.capacity() * sizeof(std::uint16_t);
    if (bytes == 0) return;
    const std::lock_guard lock(mutex_);
    if (idle_bytes_ + bytes > kIdleBytes) return;  // freed as before
    idle_bytes_ += bytes;
    idle_.push_back(std::move(storage));
  }

 private:
  // About 40 frames of 1024 x 512 or 10 of 1920 x 1080: a trial's worth at the demo's size.
  static constexpr std::size_t kIdleBytes = std::size_t{128} << 20;
  std::mutex mutex_;
  std::vector<std::vector<std::uint16_t>> idle_;
  std::size_t idle_bytes_ = 0;
};

// One row of RGBA floats to RGB halves, half_from_float's bits value for value.
void row_to_halves(const float* in, std::uint16_t* out, std::size_t pixels) {
  for (std::size_t x = 0; x < pixels; ++x)
    for (std::size_t c = 0; c < 3; ++c) out[3 * x + c] = half_from_float(in[4 * x + c]);
}

#if defined(__x86_64__)
// The same with the F16C instruction, four values a pixel at once (round to nearest even, as
// half_from_float; subnormal halves alike). It differs from half_from_float only where that one
// clamps (magnitudes from 65520 on, infinities) and for NaN payloads: a pixel with such a value in
// R, G or B is converted by half_from_float. A dynamic frame's changed rectangle in the demo is most
// of the 1024 x 512 frame: about 2 ms of the worker's frame by the scalar loop.
__attribute__((target("avx,f16c"))) void row_to_halves_f16c(const float* in, std::uint16_t* out, std::size_t pixels) {
  const __m128 magnitude_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 clamped_from = _mm_set1_ps(65520.0f);
  for (std::size_t x = 0; x < pixels; ++x) {
    const __m128 rgba = _mm_loadu_ps(in + 4 * x);
    // Not below 65520 in magnitude, or unordered (NaN).
    const __m128 special = _mm_cmp_ps(_mm_and_ps(rgba, magnitude_mask), clamped_from, _CMP_NLT_UQ);
    if ((_mm_movemask_ps(special) & 0x7) != 0) {
      row_to_halves(in + 4 * x, out + 3 * x, 1);
      continue;
    }
    const __m128i halves = _mm_cvtps_ph(rgba, _MM_FROUND_TO_NEAREST_INT);
    const auto bits = static_cast<std::uint64_t>(_mm_cvtsi128_si64(halves));
    std::memcpy(out + 3 * x, &bits, 3 * sizeof(std::uint16_t));  // little endian: R, G, B first
  }
}
#endif

void to_halves(const float* in, std::uint16_t* out, std::size_t pixels) {
#if defined(__x86_64__)
  static const bool f16c = __builtin_cpu_supports("avx") && __builtin_cpu_supports("f16c");
  if (f16c) return row_to_halves_f16c(in, out, pixels);
#endif
  row_to_halves(in, out, pixels);
}

}  // namespace

GlaredRegion::~GlaredRegion() { HalfStoragePool::instance().give(std::move(half_rgb)); }

void fill_half_storage(std::size_t values) { HalfStoragePool::instance().fill(values); }

GlaredRegion gpu_region(std::vector<GlaredRegion::GpuPart> parts) {
  GlaredRegion region;
  region.serial = new_image_token();
  PixelRect bound;
  for (const GlaredRegion::GpuPart& part : parts) bound = bounding_rect(bound, part.view);
  region.x0_px = bound.x_px;
  region.y0_px = bound.y_px;
  region.width_px = bound.width_px;
  region.height_px = bound.height_px;
  region.gpu_parts = std::move(parts);
  return region;
}

GlaredRegion changed_region(const ImageRGBA& composed, const ImageRGBA& glared, RegionPrecision precision,
                            const std::optional<PixelRect>& differs_within) {
  const auto pixel_bytes = 4 * sizeof(float);
  // The pixels compared: the whole frame, or its part in the box the caller knows the differences
  // lie in (0 x 0 when they share none).
  const PixelRect compared = differs_within ? intersection(*differs_within, image_rect(glared)) : image_rect(glared);
  const int left = compared.x_px, top = compared.y_px, right = compared.right_px(), bottom = compared.bottom_px();
  int x0 = glared.width_px, y0 = glared.height_px, x1 = -1, y1 = -1;
  for (int y = top; y < bottom && left < right; ++y) {
    const float* a = composed.pixel(0, y);
    const float* b = glared.pixel(0, y);
    if (std::memcmp(a + 4 * left, b + 4 * left, pixel_bytes * static_cast<std::size_t>(right - left)) == 0) continue;
    int first = left, last = right - 1;
    while (std::memcmp(a + 4 * first, b + 4 * first, pixel_bytes) == 0) ++first;
    while (std::memcmp(a + 4 * last, b + 4 * last, pixel_bytes) == 0) --last;
    x0 = std::min(x0, first), x1 = std::max(x1, last), y0 = std::min(y0, y), y1 = y;
  }
  GlaredRegion region;
  region.serial = new_image_token();
  if (x1 < 0) return region;
  region.x0_px = x0;
  region.y0_px = y0;
  region.width_px = x1 - x0 + 1;
  region.height_px = y1 - y0 + 1;
  const auto width = static_cast<std::size_t>(region.width_px);
  // Bottom-up: region row y - y0 from the top is row y1 - y from the bottom.
  if (precision == RegionPrecision::exact) {
    region.exact_rgba.resize(4 * width * static_cast<std::size_t>(region.height_px));
    for (int y = y0; y <= y1; ++y)
      std::copy_n(glared.pixel(x0, y), 4 * width, region.exact_rgba.data() + 4 * width * static_cast<std::size_t>(y1 - y));
    return region;
  }
  region.half_rgb = HalfStoragePool::instance().take(3 * width * static_cast<std::size_t>(region.height_px));
  for (int y = y0; y <= y1; ++y)
    to_halves(glared.pixel(x0, y), region.half_rgb.data() + 3 * width * static_cast<std::size_t>(y1 - y), width);
  return region;
}

void mark_changes_since(GlaredRegion& region, const GlaredRegion& previous) {
  const auto width = static_cast<std::size_t>(region.width_px);
  const std::size_t pixels = width * static_cast<std::size_t>(region.height_px);
  // The frame before at half precision, or exact (an interval's frame 0): then its values are
  // compared as the halves they round to, row by row.
  const bool previous_exact = previous.half_rgb.empty() && previous.exact_rgba.size() == 4 * pixels;
  if (region.half_rgb.empty() || region.half_rgb.size() != 3 * pixels || previous.serial == 0 ||
      (!previous_exact && previous.half_rgb.size() != region.half_rgb.size()) || region.x0_px != previous.x0_px ||
      region.y0_px != previous.y0_px || region.width_px != previous.width_px || region.height_px != previous.height_px)
    return;
  const auto row_values = 3 * width;
  const std::size_t pixel_bytes = 3 * sizeof(std::uint16_t);
  std::vector<std::uint16_t> previous_row(previous_exact ? row_values : 0);
  int x0 = region.width_px, x1 = -1, first_row = -1, last_row = -1;  // rows bottom-up, as stored
  for (int r = 0; r < region.height_px; ++r) {
    const std::uint16_t* a = previous_row.data();
    if (previous_exact)
      to_halves(previous.exact_rgba.data() + 4 * width * static_cast<std::size_t>(r), previous_row.data(), width);
    else
      a = previous.half_rgb.data() + row_values * static_cast<std::size_t>(r);
    const std::uint16_t* b = region.half_rgb.data() + row_values * static_cast<std::size_t>(r);
    if (std::memcmp(a, b, row_values * sizeof(std::uint16_t)) == 0) continue;
    int first = 0, last = region.width_px - 1;
    while (std::memcmp(a + 3 * first, b + 3 * first, pixel_bytes) == 0) ++first;
    while (std::memcmp(a + 3 * last, b + 3 * last, pixel_bytes) == 0) --last;
    x0 = std::min(x0, first), x1 = std::max(x1, last);
    if (first_row < 0) first_row = r;
    last_row = r;
  }
  region.previous_serial = previous.serial;
  if (x1 < 0) {
    region.changed_since_previous = PixelRect{};
    return;
  }
  // Stored row r from the bottom is frame row y0 + height - 1 - r.
  region.changed_since_previous = PixelRect{region.x0_px + x0, region.y0_px + region.height_px - 1 - last_row,
                                            x1 - x0 + 1, last_row - first_row + 1};
}

ImageRGBA region_pixels(const GlaredRegion& region) {
  ImageRGBA image(region.width_px, region.height_px, 1.0f);
  const auto width = static_cast<std::size_t>(region.width_px);
  if (!region.exact_rgba.empty()) {
    for (int y = 0; y < region.height_px; ++y)
      std::copy_n(region.exact_rgba.data() + 4 * width * static_cast<std::size_t>(region.height_px - 1 - y), 4 * width,
                  image.pixel(0, y));
    return image;
  }
  for (int y = 0; y < region.height_px; ++y) {
    const std::uint16_t* in = region.half_rgb.data() + 3 * width * static_cast<std::size_t>(region.height_px - 1 - y);
    float* out = image.pixel(0, y);
    for (std::size_t x = 0; x < width; ++x)
      for (std::size_t c = 0; c < 3; ++c) out[4 * x + c] = float_from_half(in[3 * x + c]);
  }
  return image;
}

std::size_t prepared_frames_bound_bytes(int width_px, int height_px, int frames) {
  const auto pixels = static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  if (frames <= 0) return 0;
  return pixels * 4 * sizeof(float) + static_cast<std::size_t>(frames - 1) * pixels * 3 * sizeof(std::uint16_t);
}

}  // namespace glarelab
