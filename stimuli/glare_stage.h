#pragma once
// Applies a glare condition to a composed HDR stimulus frame (cd/m2, linear Rec.709) at a session
// time: control returns the frame unchanged; static uses the eye frozen at GlareSpec::static_time_s;
// dynamic the eye of glare/eye/eye_model.h at the frame's time. The glare itself is Ritschel et al. 2009
// sections 4-5: aperture -> monochromatic PSF at 575 nm -> spectral PSF (chromatic blur) -> mapped
// onto the display's pixels (glare/wave/psf_scale.h) -> FFT convolution, the PSF and the convolution both
// by the compute backend GlareSpec::backend picks (glare/glare_backend.h: cpu, gl or auto, which
// on the CPU is the planned float32 path).
//
// "Model only what a scene needs": the convolution is skipped when the glare cannot be visible
// anywhere in the frame (bound below), and the report says when the fibre gratings are behind the
// pupil (the eye model then leaves them out of the aperture; they change nothing).
//
// Gaze-contingent glare (GlareSpec::gaze_window_px > 0; Luidolt 2020, 5.2.3): the convolution is
// done in a power-of-two window around the gaze (exact there) and blended in with a Gaussian
// falloff (glare/cpu/gaze_window_convolution.h); without a gaze the window is centred on the display.
//
// Tracker inputs (dynamic eye only): a measured pupil replaces the model's (record_measured_pupil)
// and, with blink_source tracker, detected blinks drive the lids (set_detected_blinks).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/display_spec.h"
#include "core/gl/gl_context.h"
#include "glare/analytic/analytic_glare.h"
#include "glare/analytic/ciliary_corona.h"
#include "glare/analytic/lenticular_halo.h"
#include "glare/analytic/pixel_solid_angle.h"
#include "glare/refraction/dioptric_power.h"
#include "glare/eye/eye_model.h"
#include "glare/cpu/gaze_window_convolution.h"
#include "glare/glare_backend.h"
#include "glare/wave/psf.h"
#include "glare/glare_spec.h"
#include "glare/cpu/lit_regions.h"
#include "core/image.h"
#include "stimuli/gpu_hybrid_finish.h"

namespace glarelab {

struct GlareFrameReport {
  GlareMode mode = GlareMode::control;
  bool convolved = false;          // false for control and for skipped frames
  std::string skip_reason;         // non-empty when a dynamic or static frame was not convolved
  double pupil_diameter_mm = 0.0;  // 0 for control
  bool gratings_in_pupil = false;
  // The human eye: the share of the light its fibre gratings send into the lenticular halo
  // (glare/analytic/lenticular_halo.h); 0 when the pupil hides them.
  double halo_energy = 0.0;
  // The human eye: the compact bright sources whose glare carries the ciliary corona's lines
  // (glare/analytic/ciliary_corona.h); 0 when the frame has none.
  int corona_sources = 0;
  // The lids closed the pupil completely (a blink): no light, no PSF. A dynamic eye then holds the
  // PSF of the last frame it saw open (a closed eye's PSF is undefined, and dropping the glare for
  // the ~0.1 s of closure would flash the frame); with no such frame the glare is skipped.
  bool eye_closed = false;
  GlareModel model = GlareModel::ritschel;
  double gain = 1.0;
  // Spencer's mixture used (spencer, and the hybrid's Spencer far field; the human eye's is CIE's).
  std::optional<spencer::Mixture> spencer_mixture;
  // Upper bound of max_x |glare(x) - frame(x)| / max(frame(x), floor) (see visibility_bound()).
  double visibility_bound = 0.0;
  double wing_fraction = 0.0;      // PSF energy outside the central display pixel (largest channel)
  // Gaze window: set when GlareSpec::gaze_window_px > 0 and the frame was convolved.
  std::optional<GazeWindow> window;
  // Where the glared frame can differ from the frame: when set, it equals the frame bit for bit
  // outside these boxes (its lit boxes grown by the PSF's reach, clipped to the frame; none when
  // nothing changed). Not set: it may differ anywhere (analytic and hybrid glare, a gaze window,
  // a gain other than 1, source = "excess").
  std::optional<std::vector<PixelRect>> changed_boxes;
  // Luidolt's kernel (model luidolt): how its grid was enlarged to sample Eq. 5.6, when it was.
  std::string sampling_note;
};

// What GlareStage::apply finds out about a frame before it glares it, kept for the frames that bring
// the same image again (a position's layer, or the seen frame, on every frame of an interval), so
// that each frame does not scan the whole image again. The image must not change while its facts
// are kept: one FrameFacts per image, made anew with it.
struct FrameFacts {
  std::optional<std::pair<double, double>> luminance_range_cd_m2;  // smallest and largest Rec.709 luminance
  std::map<int, std::vector<PixelRect>> lit_boxes;                  // glare/cpu/lit_regions.h, by gap (the PSF's size)
  // The hybrid and human eyes: the token of the state the stage keeps for this image (0: none yet),
  // so that a frame bringing it again is known without comparing its pixels.
  std::uint64_t glare_source_token = 0;
  // The GL engine: the token under which its perception stages keep this image on the GPU (0: none
  // yet), so that the frames of an interval upload it once, not once a frame.
  std::uint64_t gpu_scene_token = 0;
};

// A gaze point in normalised display coordinates (0..1 from the left and from the top).
struct GazePoint {
  double x = 0.5;
  double y = 0.5;
};

// A blink an eye tracker detected, on the session clock; offset +infinity while still closed.
struct DetectedBlink {
  double onset_s = 0.0;
  double offset_s = 0.0;
};

// Fraction of a display-scale PSF's energy outside its central pixel, largest over channels.
double psf_wing_fraction(const Psf& display_psf);
// Bound on the relative change glare makes anywhere in a frame. With a unit-sum PSF P and zero
// outside the image, glare(x) - L(x) = sum_{d != 0} (L(x - d) - L(x)) P(d), and for L >= 0 each
// |L(x - d) - L(x)| <= L_peak, so |change(x)| <= L_peak * wing_fraction; relative to
// max(L(x), floor) >= max(L_min, floor) this gives L_peak * wing / max(L_min, floor).
double visibility_bound(double peak_cd_m2, double min_cd_m2, double wing_fraction, double floor_cd_m2);


// Throws PsfScaleError (glare/wave/psf_scale.h) when this glare cannot be shown at this display's pixel
// scale (a PSF narrower than two display pixels, or coarser than one): found before a session
// writes anything, not at its first glare trial.
void check_glare_fits_display(const GlareSpec& spec, const DisplaySpec& display);

class GlareStage {
 public:
  // `seed` seeds the eye model (the session seed). The compute backend is made on first use (or by
  // backend_reason()); "gl" without an OpenGL 4.5 context throws DisplayError then. The GL backend
  // works in a context of its own, made by `gl_context` (empty: no GL; "auto" takes the CPU): a
  // caller drawing with another context makes it current again.
  GlareStage(const GlareSpec& spec, const DisplaySpec& display, std::uint64_t seed, GlContextFactory gl_context = {});
  ~GlareStage();

  // `gaze`: where the participant looks, for the gaze window (ignored when gaze_window_px is 0;
  // nothing: the display centre).
  // `field_luminance_cd_m2`: what the eye adapts to; nothing: the frame's mean luminance. A frame
  // split into layers (stimuli/position_glare.h) passes the whole frame's mean for every layer.
  // `facts`: the frame's facts, used where known and filled where not (nothing: found afresh).
  ImageRGBA apply(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report = nullptr,
                  const std::optional<GazePoint>& gaze = std::nullopt,
                  std::optional<double> field_luminance_cd_m2 = std::nullopt, FrameFacts* facts = nullptr);

  // apply() with the glared frame left on the GPU where it can be: a frame glared whole by a
  // wave-optics kernel (Ritschel, Luidolt) or by the hybrid and human eyes (their near part there,
  // their far part and halo made on the host once per composed frame: GpuHybridFinish) at gain 1
  // with the frame as its source and no gaze window, on a backend that keeps frames on the GPU
  // (GlareBackend::convolve_on_gpu: the GL backend). Then `gpu_buffer` names the backend's buffer holding it (RGBA32F, ImageRGBA's layout,
  // in the backend's GL context, valid until the backend's next call) and `image` is empty; else
  // `gpu_buffer` is 0 and `image` is apply()'s.
  struct GlaredOnGpu {
    unsigned gpu_buffer = 0;
    ImageRGBA image;
  };
  GlaredOnGpu apply_on_gpu(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report,
                           const std::optional<GazePoint>& gaze, std::optional<double> field_luminance_cd_m2,
                           FrameFacts* facts);

  // The glare model and gain of the frames to come (a trial's condition: the "glare_model" and
  // "glare_gain" columns); until called, GlareSpec::model and 1.
  void set_condition(GlareModel model, double gain);

  // The observer's residual refraction error of the frames to come (a trial's condition:
  // runner/session/condition_refraction.h; docs/REFRACTION.md, "In a session"): every wave-optics
  // PSF (static, dynamic, the hybrid's near field) takes it as geometry.refraction_error, its
  // spectral PSF with one FFT per wavelength and the eye's LCA (glare/wave/chromatic_psf.h). Nothing (the
  // default): the observer's optics are not modelled, and every PSF is the eye's without a refraction.
  // The frames' backend computes such a PSF itself (takes_chromatic_psf, glare/glare_backend.h): the
  // planned float32 path of "auto" on a CPU with float32 FFTs, "cpu" and "gl" with theirs.
  void set_refraction(std::optional<DioptricPower> residual_error);
  // One sentence for the record: how PSFs with a refraction are computed, and by what.
  std::string refraction_backend_reason();

  // The analytic engine (Spencer or CIE, or the hybrid's far field) for frames of this size, made
  // on first use: its kernel is integrated over the display's pixels once (seconds for a full
  // screen), so a session makes it before its first trial.
  AnalyticGlare& analytic_for(GlareModel model, int width_px, int height_px);
  // The human eye's lenticular halo (glare/analytic/lenticular_halo.h) for frames of this size, made
  // on first use: its kernel depends on the display and the fibre gratings, not on the pupil, so a
  // session makes it before its first trial with the far field's kernel (a fifth of a second on
  // two cores at 640 x 448, which the first glare frame would otherwise take).
  LenticularHaloGlare& lenticular_halo_for(int width_px, int height_px);
  // The frames' pixel solid angles (glare/analytic/pixel_solid_angle.h): the analytic kernels carry
  // energy per pixel, the frames luminance.
  const PixelSolidAngle& solid_angle_for(int width_px, int height_px);

  // The spectral PSF at the display's pixel scale for a mode and time (not for control), with the
  // eye adapted to `field_luminance_cd_m2`; nothing when the lids close the pupil completely.
  std::optional<Psf> display_psf(GlareMode mode, double time_s, double field_luminance_cd_m2, EyeState* state = nullptr);

  // The dynamic eye sees a frame of this field luminance at time_s without its glare being
  // computed: the eye's adaptation history (pupil) becomes what computing the frame would have
  // made it. A preview (glarelab render) passes through the trials before the one it shows this
  // way. The frame is remembered, so that a later frame in a blink holds the PSF of the last open
  // one as in the session that computed them all: that PSF is computed then, from the latest
  // remembered frame back until one is open (the eye at a past time is a function of the time,
  // the seed and the history up to it).
  void record_dynamic_frame(double time_s, double field_luminance_cd_m2);
  // The backend in use, made now if not yet: one sentence saying what was picked and why.
  const std::string& backend_reason();
  GlareBackend& backend();

  // What the dynamic eye is adapted to before its first frame: a session's display background,
  // which the participant looked at (fixation, inter-trial interval, screens) before the first
  // stimulus frame. Its field luminance then starts there and moves to the frames' means by
  // Luidolt 2020 Eq. 5.2 (glare/eye/pupil_model.h), as the perception stages' eye does. Not given
  // (a stage outside a session): the eye starts adapted to its first frame. Call before any frame.
  void set_dynamic_eye_start(double field_luminance_cd_m2);

  // The tracker's filtered pupil from time_s on (dynamic eye; see EyeModel::record_measured_pupil).
  void record_measured_pupil(double time_s, double diameter_mm);
  // Every blink detected so far, onsets ascending (the last one may still be open): from now on
  // they, not the lids' own schedule, close the dynamic eye.
  void set_detected_blinks(const std::vector<DetectedBlink>& blinks);

 private:
  // apply()'s work; with `gpu_buffer` the frame's glare is left on the GPU where it can be
  // (apply_on_gpu), the buffer named there and an empty image returned.
  ImageRGBA apply_to(const ImageRGBA& frame_cd_m2, GlareMode mode, double time_s, GlareFrameReport* report,
                     const std::optional<GazePoint>& gaze, std::optional<double> field_luminance_cd_m2,
                     FrameFacts* facts, unsigned* gpu_buffer);
  EyeModel& eye_for(GlareMode mode, double field_luminance_cd_m2);
  // `changed`, when given, receives the boxes outside which the result is the frame itself.
  // `facts`: the frame's, for its lit boxes (nothing: found afresh).
  ImageRGBA convolve_frame(const ImageRGBA& frame, const Psf& display_psf, std::vector<PixelRect>* changed = nullptr,
                           FrameFacts* facts = nullptr);
  ImageRGBA convolve_gaze_window(const ImageRGBA& frame, const Psf& display_psf, const GazeWindow& window);
  // The spectral PSF's options of every frame (the backend's layout).
  PsfOptions psf_options() const;
  // The wave-optics PSF of a frame (Ritschel, and the hybrid's near part), with blinks held; nothing
  // when the eye is closed and no open frame came before (r.skip_reason says so).
  std::optional<Psf> wave_psf(GlareMode mode, double time_s, double mean_cd_m2, GlareFrameReport& r);
  // Luidolt 2020's kernel (glare/wave/luidolt_kernel.h) on the display's pixels for the eye's pupil at
  // time_s: static particles from the session seed; the pupil frozen (static) or the eye's (dynamic,
  // the thesis' tracked pupil), clamped to the thesis' 2-8 mm. Kept per pupil diameter.
  Psf luidolt_psf(GlareMode mode, double time_s, double mean_cd_m2, GlareFrameReport& r);
  // The light the glare spreads with GlareSpec::source "excess": the frame's excess over the display
  // peak ("frame": the frame itself, used without a copy).
  ImageRGBA glare_excess(const ImageRGBA& frame) const;
  // frame + gain (glared - source), clipped at 0; gain 1 and the frame as source: glared itself.
  ImageRGBA with_gain(const ImageRGBA& frame, const ImageRGBA& source, ImageRGBA glared) const;
  ImageRGBA apply_analytic(const ImageRGBA& frame, const ImageRGBA& source, double mean_cd_m2, GlareFrameReport& r);
  // stimuli/glare_stage_hybrid.cpp. `facts`: the frame's when the frame is the source, else nothing.
  // `gpu_buffer`: the frame left on the GPU where the backend keeps the near part there (its buffer
  // named, an empty image returned; GpuHybridFinish).
  ImageRGBA apply_hybrid(const ImageRGBA& frame, const ImageRGBA& source, GlareMode mode, double time_s,
                         double mean_cd_m2, GlareFrameReport& r, FrameFacts* facts, unsigned* gpu_buffer = nullptr);
  std::unique_ptr<GpuHybridFinish> gpu_hybrid_finish_;  // made on the first hybrid frame kept on the GPU
  // What the hybrid and human eyes keep of the last composed frame they glared (the source), for
  // the frames that bring it again (an interval's): its energies per pixel, its lit boxes by PSF
  // size, and the token under which the analytic engine, the halo and the backend keep their parts.
  struct HybridSource {
    ImageRGBA source;  // bit for bit, to know it again
    ImageRGBA energy;  // PixelSolidAngle::to_energy(source)
    std::map<int, std::vector<PixelRect>> lit_boxes;
    std::uint64_t token = 0;
    // The human eye: the frame's corona sources, found once, and the far glare with their lines
    // added (made from the analytic engine's far glare numbered far_made; -1: not yet).
    std::optional<std::vector<CompactSource>> corona_sources;
    ImageRGBA far_with_corona;
    long long far_made = -1;
    // What a frame's near part is added to and finished with: per pixel {far glare, the frame's
    // alpha} for the far glare `finish_far_of` numbered finish_far_made, and {ring - energy (0
    // without a ring), 1 / w} (w the pixel's solid angle), the ring's part made once it is given.
    ImageRGBA finish_far;
    const ImageRGBA* finish_far_of = nullptr;
    long long finish_far_made = -1;
    ImageRGBA finish_halo;
    bool finish_halo_has_ring = false;
  };
  std::optional<HybridSource> hybrid_source_;
  HybridSource& hybrid_source(const ImageRGBA& source, FrameFacts* facts);
  HandoverPixels hybrid_handover() const;
  // The human eye's CIE kernel near the source, unweighted (calibrated_near_psf's rings), made once.
  const DisplayKernel& human_near_kernel();
  std::optional<DisplayKernel> human_near_kernel_;
  // The human eye's lenticular halo on frames of one size (its kernel's spectrum made once).
  std::unique_ptr<LenticularHaloGlare> lenticular_halo_;
  // The human eye's far glare with the ciliary corona's lines of the kept frame's compact sources:
  // the far glare itself when it has none. Made once per composed frame.
  const ImageRGBA& far_glare_with_corona(HybridSource& kept, const ImageRGBA& far_glare, long long far_made,
                                         GlareFrameReport& r);
  std::unique_ptr<CiliaryCorona> corona_;
  // The kept frame's finish terms (HybridSource::finish_far, finish_halo) for this far glare and
  // ring (or none), made when they are not yet.
  void make_finish_terms(HybridSource& kept, const ImageRGBA& far_glare, long long far_made, const ImageRGBA* ring,
                         const PixelSolidAngle& solid_angle);

  GlareSpec spec_;
  DisplaySpec display_;
  std::uint64_t seed_;
  GlContextFactory gl_context_;
  // The frames' backend (create_glare_backend: "auto" on the CPU is the planned float32 path).
  std::unique_ptr<GlareBackend> backend_;
  GlareBackendKind backend_kind_ = GlareBackendKind::cpu_float64;
  std::string backend_reason_;
  std::optional<DioptricPower> refraction_;
  // Dynamic: one eye for the whole session, starting adapted to dynamic_start_cd_m2_ (else to the
  // first frame it sees), recording every frame's mean luminance (its pupil follows the field
  // luminance).
  std::unique_ptr<EyeModel> dynamic_eye_;
  std::optional<double> dynamic_start_cd_m2_;
  double last_recorded_s_ = -1.0;
  // Tracker inputs, kept to hand to the dynamic eye when it is made.
  std::vector<std::pair<double, double>> measured_pupils_;
  std::optional<std::vector<DetectedBlink>> detected_blinks_;
  // Static: one frozen eye per field luminance (adapted to it), so identical frames give identical
  // glare at every time.
  std::map<double, std::unique_ptr<EyeModel>> static_eyes_;
  // Keyed by the field luminance and the refraction (absent, or E's xx, xy, yy): conditions that
  // differ only in the spectacles alternate within a session and keep their PSFs.
  using StaticPsfKey = std::tuple<double, bool, double, double, double>;
  std::map<StaticPsfKey, std::optional<Psf>> static_psfs_;
  // A static eye on a field adapting in time (the perception stages' adapted luminance, new every
  // frame) would keep an eye and a PSF per frame for the whole session: past this many field
  // luminances the caches start again (a recomputed PSF is the same; only its time is lost).
  static constexpr std::size_t kStaticCacheEntries = 32;
  std::optional<Psf> last_open_dynamic_psf_;
  // Dynamic frames recorded without their PSF (record_dynamic_frame) since the last PSF computed:
  // (time, field luminance) in time order, the candidates for the PSF a blink holds.
  std::vector<std::pair<double, double>> passed_dynamic_frames_;
  // The eye's luminance history only (apply()'s own skipped frames: no PSF in a session either).
  void record_dynamic_luminance(double time_s, double field_luminance_cd_m2);
  GlareModel condition_model_;
  double condition_gain_ = 1.0;
  std::map<std::tuple<int, int, int>, std::unique_ptr<AnalyticGlare>> analytic_;
  std::optional<PixelSolidAngle> solid_angle_;  // the frames' pixel solid angles (analytic far fields)
  std::map<double, std::pair<Psf, std::string>> luidolt_psfs_;  // by pupil diameter: display PSF, sampling note
};

}  // namespace glarelab
