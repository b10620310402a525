#pragma once
// Composes stimulus frames on the GPU. Frames are rendered into a float framebuffer (RGBA32F)
// holding luminance-calibrated linear RGB (Y in cd/m2), then encoded for the display into the
// backend's default framebuffer. Needs the backend's GL context to be current.
#include <cstdint>
#include <map>
#include <vector>

#include "core/gl/gl_objects.h"
#include "core/image.h"
#include "core/pixel_rect.h"
#include "stimuli/display_model.h"

namespace glarelab {

// A scene image on the GPU (RGBA32F), with the factor that turns its values into cd/m2.
struct SceneTexture {
  gl::Texture texture;
  int width_px = 0;
  int height_px = 0;
};

struct Placement {
  const SceneTexture* scene = nullptr;
  double scale_cd_m2 = 1.0;
  PixelRect rect;  // where the image goes
  PixelRect clip;  // what of it may be drawn (its layout column)
};

class FrameRenderer {
 public:
  FrameRenderer(int width_px, int height_px);

  SceneTexture upload(const ImageRGBA& image) const;

  // Clears to the background luminance and draws the placements into the stimulus framebuffer.
  void compose(const std::vector<Placement>& placements, double background_cd_m2);
  // Draws premultiplied overlays (stimuli/overlay_image.h: text, fixation cross) over the stimulus
  // framebuffer without clearing it: after glare (replace_stimulus), since text on the display is
  // not seen through the simulated eye. Each overlay is clipped to its `clip` rectangle.
  void compose_overlay(const std::vector<Placement>& overlays);
  // Encodes the stimulus framebuffer into the default framebuffer (clip at peak, then sRGB, gamma,
  // PQ or the calibration table: stimuli/shaders/encode_display.frag). With
  // display.bits_per_channel 8, 10 or 16 the frame is first written to a target of that depth
  // (RGBA8 with 4x4 ordered dithering, RGB10_A2, RGBA16F) and copied (blit) to the default
  // framebuffer, so the drive values are quantised to that depth whatever the backend's own
  // framebuffer holds; with 0 it is encoded straight into the default framebuffer.
  // Throws DisplayError for another depth or a calibration table larger than a texture.
  void encode_to_display(const DisplaySpec& display);
  // The same for the pixels written to the stimulus framebuffer since the last encode only (their
  // bounding rectangle, scissored; a quantised frame is copied to the default framebuffer in that
  // rectangle only), for a display framebuffer that still holds the last encode with the same
  // `display`: the offscreen displays (DisplayBackend::keeps_presented_frame). The encoding of a
  // pixel depends only on its stimulus value and position, so the result is the full encode's,
  // bit for bit. Before any encode, it is encode_to_display.
  void encode_changes_to_display(const DisplaySpec& display);
  // What encode_changes_to_display would encode (top-left origin); empty (0 x 0) when nothing changed.
  PixelRect unencoded_rect() const { return unencoded_; }

  // Counts the writes to the stimulus framebuffer (compose, overlays, replaced frames and regions):
  // a caller that drew it and finds the count unchanged knows it still holds what it drew.
  std::uint64_t stimulus_generation() const { return stimulus_generation_; }
  // Read-backs (row 0 at the top). The stimulus is in cd/m2; the display image holds drive values
  // (from the quantising target when the last encode had one, so exactly its code values / max).
  ImageRGBA read_stimulus() const;
  ImageRGBA read_display() const;
  // Overwrites the stimulus framebuffer with an image of the same size (row 0 at the top, cd/m2):
  // how a frame processed on the CPU (stimuli/glare_stage.h) returns for encoding.
  void replace_stimulus(const ImageRGBA& image);
  // Overwrites only the rectangle of the stimulus framebuffer at (x0_px, y0_px) from the top left
  // with `region` (cd/m2): a glared frame that differs from the composed one only there.
  void replace_stimulus_region(const ImageRGBA& region, int x0_px, int y0_px);
  // The same from rows already bottom-up, as OpenGL takes them, so nothing is copied: float32 RGBA
  // (4 x width x height floats), or binary16 R, G, B (3 x width x height halves, each widened to
  // float exactly; alpha becomes 1).
  void replace_stimulus_region_bottom_up(const std::vector<float>& rgba_bottom_up, int x0_px, int y0_px, int width_px,
                                         int height_px);
  void replace_stimulus_region_half_rgb(const std::vector<std::uint16_t>& rgb_bottom_up, int x0_px, int y0_px,
                                        int width_px, int height_px);
  // Only the pixels of such a region inside `part` (frame coordinates, top-left origin, within the
  // region), read in place from the region's rows: for a region that differs from the one the
  // stimulus framebuffer holds only there, the rest of its rectangle already holds its values.
  void replace_stimulus_region_half_rgb_part(const std::vector<std::uint16_t>& rgb_bottom_up, int x0_px, int y0_px,
                                             int width_px, int height_px, const PixelRect& part);

  // The same from a frame left on the GPU (the GL frame engine's, stimuli/frame_engine.h): a shader
  // storage buffer of this context holding width x height RGBA32F pixels, row 0 at the top, copied
  // into the rectangle on the GPU; nothing comes to the host.
  void replace_stimulus_region_from_buffer(unsigned buffer, int x0_px, int y0_px, int width_px, int height_px);

  // Waits until the GL work issued so far is done (glFinish): what a draw cost, timed.
  void finish() const;

  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }

  // The framebuffer encode_to_display writes the frame into: 0, the default framebuffer (a window,
  // an offscreen buffer), or a display's own float frame (the OpenXR display's, whose halves become
  // its views' images: DisplayBackend::frame_framebuffer). Set before the first encode.
  void set_display_framebuffer(unsigned framebuffer) { display_output_ = framebuffer; }

 private:
  // Checks the rectangle and uploads `values` (`channels` per pixel, GL type `type`) into it, rows
  // bottom-up; with `part`, only the pixels of the rectangle inside it.
  void upload_stimulus_region(const void* values, std::size_t count, int channels, unsigned type, int x0_px, int y0_px,
                              int width_px, int height_px, const char* what, const PixelRect* part = nullptr);
  void draw_placements(const std::vector<Placement>& placements, bool overlay);
  // Widens unencoded_ by `rect` (clipped to the frame).
  void mark_unencoded(const PixelRect& rect);
  void encode_rect(const DisplaySpec& display, const PixelRect& rect);
  // (Re)creates the quantising target for `bits_per_channel` when it differs from the current one.
  void prepare_display_target(int bits_per_channel);
  // Uploads the calibration table (and its gains at each 8-bit code, for dithering) when it
  // differs from the one on the GPU.
  void prepare_calibration_table(const DisplayCalibration& calibration);

  int width_px_;
  int height_px_;
  GLuint display_output_ = 0;  // where encodes go (set_display_framebuffer)
  gl::Texture stimulus_texture_;
  gl::Framebuffer stimulus_framebuffer_;
  gl::VertexArray empty_vertex_array_;  // core profile needs a bound VAO even without attributes
  gl::Program placed_image_program_;
  // encode_display.frag built for one encoding (0 sRGB, 1 gamma, 2 PQ) with or without dithering,
  // made on first use: key 2 * encoding + dither.
  unsigned encode_program(int encoding, bool dither);
  std::map<int, gl::Program> encode_programs_;
  int target_bits_ = 0;                  // depth of display_target_; 0: none
  gl::Texture display_target_;           // quantising target of the last encode (bits 8, 10, 16)
  gl::Framebuffer display_framebuffer_;  // its framebuffer
  bool read_from_target_ = false;        // the last encode went through display_target_
  std::uint64_t stimulus_generation_ = 0;
  PixelRect unencoded_;     // written since the last encode (top-left origin); 0 x 0: nothing
  bool encoded_once_ = false;
  gl::Program encode_table_program_;     // encoding = "table" (encode_display_table.frag), built on first use
  gl::Program from_buffer_program_;      // stimulus_from_buffer.comp, built on first use
  gl::Texture calibration_texture_;      // rows x 1 RGBA32F: (drive, gain r, gain g, gain b)
  gl::Texture code_gain_texture_;        // 256 x 1 RGBA32F: gains at drive k / 255
  DisplayCalibration uploaded_calibration_;
};

}  // namespace glarelab
