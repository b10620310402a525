#include "stimuli/position_glare.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/gl/shader_program.h"
#include "core/image_token.h"
#include "core/parallel_for.h"
#include "glare/cpu/fftw_float_plan.h"

namespace glarelab {

namespace {

void check_layer_sizes(const ImageRGBA& composed_cd_m2, const std::vector<GlareLayer>& layers) {
  for (const GlareLayer& layer : layers)
    if (layer.image_cd_m2.width_px != composed_cd_m2.width_px || layer.image_cd_m2.height_px != composed_cd_m2.height_px)
      throw std::invalid_argument("glare layers: a layer of " + std::to_string(layer.image_cd_m2.width_px) + "x" +
                                  std::to_string(layer.image_cd_m2.height_px) + " px for a frame of " +
                                  std::to_string(composed_cd_m2.width_px) + "x" +
                                  std::to_string(composed_cd_m2.height_px) + " px");
}

bool same_gaze(const std::optional<GazePoint>& a, const std::optional<GazePoint>& b) {
  return a.has_value() == b.has_value() && (!a || (a->x == b->x && a->y == b->y));
}

// result = base + each of `adding` in order, per colour value (alpha: the base's), for the interval's
// kept base (StaticLayerGlare::SumBase). The glares' addresses are taken once, so a value costs one
// load per glare, not the three dependent loads of glare_of[glaring[k]]->rgba. `result` may be the
// buffer of one of `adding`: each value is read before it is written.
void add_glares_to_base(const ImageRGBA& base, const std::vector<const float*>& adding, ImageRGBA& result) {
  const float* partial = base.rgba.data();
  float* out = result.rgba.data();
  const auto pixels = static_cast<int>(result.rgba.size() / 4);
  if (adding.size() == 1 && adding.front() == out) {
    // One glare added, held in the result's own buffer (a dynamic side beside kept ones): added in
    // place, base + glare as glare + base (the same float, addition being commutative).
    parallel_chunks(pixels, kGlareCpuThreads, [&](int first, int last) {
      for (auto p = 4 * static_cast<std::size_t>(first); p < 4 * static_cast<std::size_t>(last); p += 4) {
        out[p] += partial[p];
        out[p + 1] += partial[p + 1];
        out[p + 2] += partial[p + 2];
        out[p + 3] = partial[p + 3];
      }
    });
    return;
  }
  parallel_chunks(pixels, kGlareCpuThreads, [&](int first, int last) {
    for (auto p = 4 * static_cast<std::size_t>(first); p < 4 * static_cast<std::size_t>(last); p += 4) {
      for (std::size_t c = 0; c < 3; ++c) {
        float value = partial[p + c];
        for (const float* glare : adding) value += glare[p + c];
        out[p + c] = value;
      }
      out[p + 3] = partial[p + 3];
    }
  });
}

}  // namespace

ImageRGBA apply_layered_glare(GlareStage& stage, const ImageRGBA& composed_cd_m2, const std::vector<GlareLayer>& layers,
                              double time_s, const std::optional<GazePoint>& gaze,
                              std::vector<GlareFrameReport>* reports, std::optional<double> field_luminance,
                              StaticLayerGlare* kept) {
  const double field_luminance_cd_m2 = field_luminance ? *field_luminance : mean_luminance(composed_cd_m2);
  check_layer_sizes(composed_cd_m2, layers);
  // Each glaring layer's glare. A control layer's glare is the layer itself, so its two terms in
  // the sum below cancel and are left out (exactly: where it is not zero the composed frame holds
  // the same value and no other layer is drawn).
  std::vector<std::size_t> glaring;
  std::vector<ImageRGBA> glared(layers.size());
  std::vector<const ImageRGBA*> glare_of(layers.size(), nullptr);  // each glaring layer's glare, computed or kept
  // Where each glaring layer's glare changed it (GlareFrameReport::changed_boxes); nothing: anywhere.
  std::vector<std::optional<std::vector<PixelRect>>> changed_of(layers.size());
  if (kept != nullptr && kept->layers.size() != layers.size()) kept->layers.assign(layers.size(), std::nullopt);
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const GlareLayer& layer = layers[l];
    if (layer.mode == GlareMode::control) continue;
    glaring.push_back(l);
    std::optional<StaticLayerGlare::Kept>* keep =
        kept != nullptr && layer.mode == GlareMode::static_eye ? &kept->layers[l] : nullptr;
    if (keep != nullptr && *keep && !(*keep)->glared_on_gpu && same_gaze((*keep)->gaze, gaze) &&
        (*keep)->field_luminance_cd_m2 == field_luminance_cd_m2) {
      glare_of[l] = &(*keep)->glared_cd_m2;
      changed_of[l] = (*keep)->report.changed_boxes;
      if (reports != nullptr) reports->push_back((*keep)->report);
      continue;
    }
    GlareFrameReport report;
    glared[l] = stage.apply(layer.image_cd_m2, layer.mode, time_s, &report, gaze, field_luminance_cd_m2, &layer.facts);
    if (layer.keep_peak) {
      const double before = max_luminance(layer.image_cd_m2), after = max_luminance(glared[l]);
      if (before > 0.0 && after > 0.0) {
        const auto scale = static_cast<float>(before / after);
        for (std::size_t i = 0; i < glared[l].rgba.size(); ++i)
          if (i % 4 != 3) glared[l].rgba[i] *= scale;
      }
    }
    changed_of[l] = report.changed_boxes;
    if (reports != nullptr) reports->push_back(report);
    if (keep != nullptr) {
      *keep = StaticLayerGlare::Kept{glared[l], report, gaze, field_luminance_cd_m2, nullptr, new_image_token()};
      glare_of[l] = &(*keep)->glared_cd_m2;
    } else {
      glare_of[l] = &glared[l];
    }
  }
  if (glaring.empty()) return composed_cd_m2;
  // Per value: composed - layer_1 - ... - layer_n + glared_1 + ... + glared_n, in that order.
  // `glares` of them added: all for the sum, the kept ones before the first glared anew for the
  // interval's base (StaticLayerGlare::SumBase).
  const auto combine_first = [&](std::size_t pixel, float* out, std::size_t glares) {
    for (std::size_t c = 0; c < 3; ++c) {
      float value = composed_cd_m2.rgba[pixel + c];
      for (const std::size_t l : glaring) value -= layers[l].image_cd_m2.rgba[pixel + c];
      for (std::size_t k = 0; k < glares; ++k) value += glare_of[glaring[k]]->rgba[pixel + c];
      out[c] = value;
    }
    out[3] = composed_cd_m2.rgba[pixel + 3];  // alpha: the composed frame's
  };
  const auto combine = [&](std::size_t pixel, float* out) { combine_first(pixel, out, glaring.size()); };
  // The result goes into the first computed layer's buffer (frame-sized, ours; a kept layer's
  // glare is copied into the cache, so its own buffer is free too): no frame-sized allocation and
  // copy more per frame. Each value is read before it is written.
  std::size_t result_layer = glaring.front();
  for (const std::size_t l : glaring)
    if (!glared[l].rgba.empty()) {
      result_layer = l;
      break;
    }
  ImageRGBA& result = glared[result_layer];
  if (result.rgba.empty()) result = ImageRGBA(composed_cd_m2.width_px, composed_cd_m2.height_px);
  const auto width = static_cast<std::size_t>(result.width_px);
  // When every glaring layer says where its glare changed it, the sum is made there only: outside
  // those boxes each glared layer is its layer, which is 0 outside its lit boxes, so the sum is the
  // composed value itself (composed - 0 + 0), copied. The demo's two lamps change a tenth of its frame.
  if (std::all_of(glaring.begin(), glaring.end(), [&](std::size_t l) { return changed_of[l].has_value(); })) {
    std::vector<PixelRect> boxes;
    for (const std::size_t l : glaring) boxes.insert(boxes.end(), changed_of[l]->begin(), changed_of[l]->end());
    parallel_chunks(result.height_px, kGlareCpuThreads, [&](int first, int last) {
      std::vector<std::pair<int, int>> spans;  // [x0, x1) of the boxes on a row, by x0; overlaps summed once
      for (int y = first; y < last; ++y) {
        spans.clear();
        for (const PixelRect& box : boxes)
          if (y >= box.y_px && y < box.bottom_px()) spans.emplace_back(box.x_px, box.right_px());
        std::sort(spans.begin(), spans.end());
        const std::size_t row = static_cast<std::size_t>(y) * width;
        int x = 0;
        for (const auto& [x0, x1] : spans) {
          if (x0 > x) std::copy_n(composed_cd_m2.rgba.data() + 4 * (row + x), 4 * (x0 - x), result.rgba.data() + 4 * (row + x));
          for (int p = std::max(x, x0); p < x1; ++p) combine(4 * (row + p), result.rgba.data() + 4 * (row + p));
          x = std::max(x, x1);
        }
        if (x < result.width_px)
          std::copy_n(composed_cd_m2.rgba.data() + 4 * (row + x), 4 * (width - x), result.rgba.data() + 4 * (row + x));
      }
    });
    return std::move(result);
  }
  // Otherwise everywhere: the background part (what no layer holds: exactly zero inside a
  // placement, which replaces the background there; the background luminance elsewhere) plus every
  // glaring layer's glare, in one pass.
  const auto pixels = static_cast<int>(result.rgba.size() / 4);
  if (kept != nullptr) {
    // From the interval's base (StaticLayerGlare::SumBase), made again when what it holds changed.
    std::vector<std::uint64_t> kept_serials;
    for (const std::size_t l : glaring) {
      if (!kept->layers[l] || glare_of[l] != &kept->layers[l]->glared_cd_m2) break;
      kept_serials.push_back(kept->layers[l]->serial);
    }
    StaticLayerGlare::SumBase& base = kept->base;
    if (base.composed != composed_cd_m2.rgba.data() || base.glaring != glaring || base.kept_serials != kept_serials ||
        base.partial_cd_m2.rgba.size() != composed_cd_m2.rgba.size()) {
      base.composed = composed_cd_m2.rgba.data();
      base.glaring = glaring;
      base.kept_serials = kept_serials;
      if (base.partial_cd_m2.rgba.size() != composed_cd_m2.rgba.size())
        base.partial_cd_m2 = ImageRGBA(composed_cd_m2.width_px, composed_cd_m2.height_px);
      float* partial = base.partial_cd_m2.rgba.data();
      parallel_chunks(pixels, kGlareCpuThreads, [&](int first, int last) {
        for (auto p = 4 * static_cast<std::size_t>(first); p < 4 * static_cast<std::size_t>(last); p += 4)
          combine_first(p, partial + p, kept_serials.size());
      });
    }
    std::vector<const float*> adding;  // the glares not in the base, in order
    for (std::size_t k = kept_serials.size(); k < glaring.size(); ++k) adding.push_back(glare_of[glaring[k]]->rgba.data());
    add_glares_to_base(base.partial_cd_m2, adding, result);
    return std::move(result);
  }
  parallel_chunks(pixels, kGlareCpuThreads, [&](int first, int last) {
    // Each value is read before it is written (result may be a glared layer's own buffer).
    for (int p = first; p < last; ++p) combine(4 * static_cast<std::size_t>(p), result.rgba.data() + 4 * static_cast<std::size_t>(p));
  });
  return std::move(result);
}

void GpuLayerSum::add(gl::GlFrameBuffer& frame, const gl::GlFrameBuffer& layer, const gl::GlFrameBuffer& glared) {
  if (!program_) program_ = gl::build_program({"stimuli/shaders/layer_glare_sum.comp"});
  const auto pixels = static_cast<GLuint>(frame.width_px()) * static_cast<GLuint>(frame.height_px());
  glUseProgram(program_.get());
  glUniform1ui(glGetUniformLocation(program_.get(), "uPixels"), pixels);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, frame.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, layer.buffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, glared.buffer());
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glDispatchCompute((pixels + 255) / 256, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  glUseProgram(0);
  gl::check_gl_error("glare layers: summing a layer's glare on the GPU");
}

std::shared_ptr<gl::GlFrameBuffer> apply_layered_glare_on_gpu(GlareStage& stage, GpuLayerSum& sum,
                                                              const ImageRGBA& composed_cd_m2,
                                                              const std::vector<GlareLayer>& layers, double time_s,
                                                              const std::optional<GazePoint>& gaze,
                                                              std::vector<GlareFrameReport>* reports,
                                                              std::optional<double> field_luminance,
                                                              StaticLayerGlare* kept) {
  for (const GlareLayer& layer : layers)
    if (layer.mode != GlareMode::control && layer.keep_peak) return nullptr;
  const double field_luminance_cd_m2 = field_luminance ? *field_luminance : mean_luminance(composed_cd_m2);
  check_layer_sizes(composed_cd_m2, layers);
  if (kept != nullptr && kept->layers.size() != layers.size()) kept->layers.assign(layers.size(), std::nullopt);
  const int width = composed_cd_m2.width_px, height = composed_cd_m2.height_px;
  auto frame = std::make_shared<gl::GlFrameBuffer>(composed_cd_m2);
  const auto add_layer = [&](const ImageRGBA& layer_cd_m2, const gl::GlFrameBuffer& glared) {
    sum.add(*frame, gl::GlFrameBuffer(layer_cd_m2), glared);
  };
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const GlareLayer& layer = layers[l];
    if (layer.mode == GlareMode::control) continue;
    std::optional<StaticLayerGlare::Kept>* keep =
        kept != nullptr && layer.mode == GlareMode::static_eye ? &kept->layers[l] : nullptr;
    if (keep != nullptr && *keep && (*keep)->glared_on_gpu && same_gaze((*keep)->gaze, gaze) &&
        (*keep)->field_luminance_cd_m2 == field_luminance_cd_m2) {
      if (reports != nullptr) reports->push_back((*keep)->report);
      add_layer(layer.image_cd_m2, *(*keep)->glared_on_gpu);
      continue;
    }
    GlareFrameReport report;
    GlareStage::GlaredOnGpu glared =
        stage.apply_on_gpu(layer.image_cd_m2, layer.mode, time_s, &report, gaze, field_luminance_cd_m2, &layer.facts);
    auto on_gpu = std::make_shared<gl::GlFrameBuffer>(width, height);
    if (glared.gpu_buffer != 0)
      on_gpu->copy_from(glared.gpu_buffer);
    else
      on_gpu->upload(glared.image);
    if (reports != nullptr) reports->push_back(report);
    add_layer(layer.image_cd_m2, *on_gpu);
    if (keep != nullptr) *keep = StaticLayerGlare::Kept{ImageRGBA(), report, gaze, field_luminance_cd_m2, on_gpu};
  }
  return frame;
}

}  // namespace glarelab
