// The glare stage's hybrid and human eyes (glare/analytic/hybrid_psf.h): the wave-optics near part
// per frame, the analytic far part and the lenticular halo kept for the composed frame while it comes
// again, and the three joined in one pass over the near part's rows as the convolution writes them.
//
// Why kept: within a dynamic interval the composed frame is the same from frame to frame and only
// the eye moves. The far glare and the halo's ring are linear in the frame and do not move with
// the eye (the halo's share, the pupil's, scales the ring), so they are made once per composed
// frame; so are the frame's energies per pixel and its lit boxes, and what the finish needs per
// pixel: the far glare with the frame's alpha, which the inverse transform adds the near part to,
// and one stream of {ring - energy, 1 / solid angle}. A frame then costs the near PSF, one
// transform of it, one product with the kept spectrum of the frame, a copy of the kept far glare
// and the inverse transform, whose rows are finished (the halo's share added, energy back to
// luminance) while in cache: the Ritschel frame's passes, with the finish's one kept stream where
// that frame compares its pixels (docs/PERFORMANCE.md, "The default eye's frame against the
// Ritschel frame"). The sum is the passes' it replaces in their
// order, near + far, + halo, / solid angle, in float32 with the solid angle's reciprocal (within a
// few float32 roundings of them). The human eye's far glare carries the ciliary
// corona's lines around the frame's compact sources (glare/analytic/ciliary_corona.h), added to a
// copy of it once per composed frame, so a frame of the interval reads the lines with the far glare.
#include <algorithm>
#include <cmath>

#include "core/image_token.h"
#include "core/parallel_for.h"
#include "core/same_pixels.h"
#include "glare/cpu/psf.h"
#include "glare/wave/psf_scale.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

bool same_rgba(const ImageRGBA& a, const ImageRGBA& b) { return same_pixel_bits(a, b) && a.depth == b.depth; }

}  // namespace

HandoverPixels GlareStage::hybrid_handover() const {
  HybridHandover handover{spec_.hybrid_handover_inner_deg, spec_.hybrid_handover_outer_deg};
  const double reach = wave_psf_reach_deg(spec_.grid_px, psf_degrees_per_pixel(kReferenceWavelengthNm, spec_.aperture_width_mm));
  if (handover.outer_deg <= 0.0) handover = default_handover(reach);
  check_handover(handover, reach);
  return handover_pixels(handover, DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm});
}

const DisplayKernel& GlareStage::human_near_kernel() {
  if (human_near_kernel_) return *human_near_kernel_;
  // The unweighted CIE kernel out to the hand-over's outer radius: the rings the near part is
  // calibrated on (a few hundred pixels, once per session).
  const int reach = static_cast<int>(std::ceil(hybrid_handover().outer_px)) + 1;
  human_near_kernel_ = analytic_display_kernel(AnalyticPsf::cie(spec_.observer_eye),
                                               DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm},
                                               reach, reach);
  return *human_near_kernel_;
}

GlareStage::HybridSource& GlareStage::hybrid_source(const ImageRGBA& source, FrameFacts* facts) {
  // The facts of an image come with it and die with it: their token names the kept state when they
  // carry its token; otherwise the pixels are compared (a new image may bring the same pixels).
  const bool same = hybrid_source_ && ((facts != nullptr && facts->glare_source_token == hybrid_source_->token) ||
                                       same_rgba(source, hybrid_source_->source));
  if (!same) {
    hybrid_source_.reset();  // until the new state is whole
    HybridSource kept;
    kept.energy = solid_angle_for(source.width_px, source.height_px).to_energy(source);
    kept.source = source;
    kept.token = new_image_token();
    hybrid_source_ = std::move(kept);
  }
  if (facts != nullptr) facts->glare_source_token = hybrid_source_->token;
  return *hybrid_source_;
}

const ImageRGBA& GlareStage::far_glare_with_corona(HybridSource& kept, const ImageRGBA& far_glare, long long far_made,
                                                   GlareFrameReport& r) {
  if (!corona_)
    corona_ = std::make_unique<CiliaryCorona>(spec_.observer_eye,
                                              DisplayGeometry{display_.viewing_distance_mm, display_.pixel_pitch_mm}, seed_);
  if (!kept.corona_sources) kept.corona_sources = compact_sources(kept.source, kept.energy, corona_->source_rule());
  r.corona_sources = static_cast<int>(kept.corona_sources->size());
  if (kept.corona_sources->empty()) return far_glare;
  if (kept.far_made != far_made) {
    kept.far_made = -1;  // until the new one is whole
    ImageRGBA lines(far_glare.width_px, far_glare.height_px, 0.0f);
    for (const CompactSource& source : *kept.corona_sources) corona_->add(source, lines, kGlareCpuThreads);
    // far + lines; the lines take from a source's own veil no more than it holds there (the
    // centroid's smooth kernel and the far glare of the source's pixels differ by rounding and by
    // the source's extent), so no pixel goes below 0.
    kept.far_with_corona = far_glare;
    for (std::size_t i = 0; i < lines.rgba.size(); i += 4)
      for (std::size_t c = 0; c < 3; ++c) {
        const float added = lines.rgba[i + c];
        if (added == 0.0f) continue;
        float& value = kept.far_with_corona.rgba[i + c];
        value = std::max(0.0f, value + added);
      }
    kept.far_made = far_made;
  }
  return kept.far_with_corona;
}

void GlareStage::make_finish_terms(HybridSource& kept, const ImageRGBA& far_glare, long long far_made, const ImageRGBA* ring,
                                   const PixelSolidAngle& solid_angle) {
  const ImageRGBA& energy = kept.energy;
  const int width = energy.width_px;
  // Per row on the glare's threads, once per composed frame (and per far glare: a new adaptation
  // may bring one), so that a frame of the interval starts from one kept image and reads one more.
  const auto rows = [&](ImageRGBA& terms, const auto& pixel) {
    terms = ImageRGBA(width, energy.height_px);
    parallel_chunks(energy.height_px, kGlareCpuThreads, [&](int first, int last) {
      for (int y = first; y < last; ++y)
        for (int x = 0; x < width; ++x) {
          const std::size_t i = 4 * (static_cast<std::size_t>(y) * width + x);
          pixel(solid_angle.relative(x, y), i, &terms.rgba[i]);
        }
    });
  };
  if (kept.finish_far_of != &far_glare || kept.finish_far_made != far_made) {
    kept.finish_far_of = nullptr;  // until the new terms are whole
    rows(kept.finish_far, [&](float, std::size_t i, float* terms) {
      for (std::size_t c = 0; c < 3; ++c) terms[c] = far_glare.rgba[i + c];
      terms[3] = energy.rgba[i + 3];
    });
    kept.finish_far_of = &far_glare;
    kept.finish_far_made = far_made;
  }
  if (kept.finish_halo.empty() || (ring != nullptr && !kept.finish_halo_has_ring)) {
    kept.finish_halo_has_ring = ring != nullptr;
    rows(kept.finish_halo, [&](float weight, std::size_t i, float* terms) {
      for (std::size_t c = 0; c < 3; ++c)
        terms[c] = ring != nullptr ? static_cast<float>(static_cast<double>(ring->rgba[i + c]) - energy.rgba[i + c]) : 0.0f;
      terms[3] = 1.0f / weight;
    });
  }
}

ImageRGBA GlareStage::apply_hybrid(const ImageRGBA& frame, const ImageRGBA& source, GlareMode mode, double time_s,
                                   double mean_cd_m2, GlareFrameReport& r, FrameFacts* facts, unsigned* gpu_buffer) {
  const std::optional<Psf> wave = wave_psf(mode, time_s, mean_cd_m2, r);
  if (!wave) return frame;
  r.wing_fraction = psf_wing_fraction(*wave);
  const bool human = condition_model_ == GlareModel::human;
  AnalyticGlare& far = analytic_for(condition_model_, frame.width_px, frame.height_px);
  far.adapt(mean_cd_m2);
  if (!human && spec_.hybrid_far_field == GlareModel::spencer) r.spencer_mixture = far.mixture();
  // The near part (s w P_wave, or the human eye's g_k w P_wave ring by ring), convolved as the
  // wave-optics PSF is (cropped to where light reaches); the far part by the analytic engine; their
  // sum is the hybrid kernel's convolution.
  const Psf near = human ? calibrated_near_psf(*wave, human_near_kernel(), hybrid_handover())
                         : hybrid_near_psf(*wave, far.energy_inside_handover(), hybrid_handover());
  // Both parts carry energy per pixel (the far kernel reaches across the display, where pixels
  // subtend less): the source's luminance to energy, the sum back to luminance.
  HybridSource& kept = hybrid_source(source, facts);
  const ImageRGBA& energy = kept.energy;
  auto boxes = kept.lit_boxes.find(near.size_px);
  if (boxes == kept.lit_boxes.end()) boxes = kept.lit_boxes.emplace(near.size_px, lit_regions(energy, near.size_px)).first;
  // The human eye's far glare carries the ciliary corona's lines around the frame's compact sources
  // (remade only when the engine computed a new far glare).
  const ImageRGBA& smooth_far_glare = far.glare(energy, kept.token);
  const ImageRGBA& far_glare =
      human ? far_glare_with_corona(kept, smooth_far_glare, far.convolutions_computed(), r) : smooth_far_glare;
  // The lenticular halo of the fibre gratings this pupil uncovers, its light taken from the
  // source's own pixel (glare/analytic/lenticular_halo.h): halo_energy (ring - source).
  const ImageRGBA* ring = nullptr;
  if (human) {
    const HaloGratings gratings = halo_gratings(spec_.eye);
    // Made before any pupil uncovers the gratings (with the eye's first frame at the latest;
    // lenticular_halo_for): a pupil that first uncovers them later in the session (a dynamic
    // interval's larger pupil after static ones) then costs a frame of that interval nothing extra.
    LenticularHaloGlare& halo = lenticular_halo_for(frame.width_px, frame.height_px);
    r.halo_energy = lenticular_halo_energy(eye_for(mode, mean_cd_m2).lens().grating_lines(), gratings, r.pupil_diameter_mm);
    if (r.halo_energy > 0.0) ring = &halo.ring(energy, kept.token);
  }
  const double halo_energy = r.halo_energy;
  const PixelSolidAngle& solid_angle = solid_angle_for(source.width_px, source.height_px);
  // Per pixel, in the order of the passes this replaces (AnalyticGlare::add_convolution,
  // LenticularHaloGlare::add, PixelSolidAngle::to_luminance): near + far, + h (ring - energy), to
  // luminance. The near part is added to the kept far glare as the inverse transform writes it;
  // this finishes each row from one kept stream (make_finish_terms).
  const float halo_share = static_cast<float>(halo_energy);
  const RowFinish finish = [&](int y, int x_from, int x_to, float* rgba) {
    const float* terms = &kept.finish_halo.rgba[4 * (static_cast<std::size_t>(y) * frame.width_px + x_from)];
    const float h = halo_share;  // a local: the row's stores cannot change it
    if (ring == nullptr)
      for (int x = x_from; x < x_to; ++x, rgba += 4, terms += 4) {
        const float to_luminance = terms[3];
        rgba[0] *= to_luminance;
        rgba[1] *= to_luminance;
        rgba[2] *= to_luminance;
      }
    else
      for (int x = x_from; x < x_to; ++x, rgba += 4, terms += 4) {
        const float to_luminance = terms[3];
        rgba[0] = (rgba[0] + h * terms[0]) * to_luminance;
        rgba[1] = (rgba[1] + h * terms[1]) * to_luminance;
        rgba[2] = (rgba[2] + h * terms[2]) * to_luminance;
      }
  };
  if (gpu_buffer != nullptr) {
    // The near part convolved whole on the GPU and finished there by the same per-pixel sum. The
    // kept energy image's token names it to the convolution, which then keeps its spectrum without
    // comparing its pixels (33 MB at 1920 x 1080) each frame.
    if (const unsigned near_on_gpu = backend().convolve_on_gpu(energy, near, kept.token); near_on_gpu != 0) {
      if (!gpu_hybrid_finish_) gpu_hybrid_finish_ = std::make_unique<GpuHybridFinish>();
      *gpu_buffer = gpu_hybrid_finish_->finish(near_on_gpu, energy, far_glare, ring, halo_energy, solid_angle, kept.token);
      r.convolved = true;
      return {};
    }
  }
  make_finish_terms(kept, far_glare, far.convolutions_computed(), ring, solid_angle);
  ImageRGBA glared;
  backend().convolve_regions_finished(energy, boxes->second, near, glared, finish, kept.token, &kept.finish_far);
  r.convolved = true;
  return with_gain(frame, source, std::move(glared));
}

}  // namespace glarelab
