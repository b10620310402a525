#include "protocols/generated_scene_config.h"

#include "core/number_text.h"

namespace glarelab {
namespace {

// Bounds: 4096 px a side is 2^24 pixels (256 MiB of RGBA floats), drawn when the scenes load: larger
// than any stimulus window, small enough that a typo cannot exhaust memory; angles that a screen in
// front of an observer can subtend.
constexpr std::int64_t kMaxGeneratedScenePx = 4096;
constexpr double kMinDiameterDeg = 1e-4, kMaxDiameterDeg = 120.0;

}  // namespace

GeneratedSceneSpec read_generated_scene(TableReader& reader, const DisplaySpec& display) {
  GeneratedSceneSpec spec;
  const std::string name = *reader.string("generator");
  if (name == "disc_annulus") spec.generator = SceneGenerator::disc_annulus;
  else if (name == "light_source") spec.generator = SceneGenerator::light_source;
  else if (name == "desk_lamp") spec.generator = SceneGenerator::desk_lamp;
  else
    reader.fail("generator", "unknown generator '" + name + "' (supported: 'disc_annulus', 'light_source', 'desk_lamp')");
  spec.size_px = static_cast<int>(reader.integer_in_range("size_px", spec.size_px, 1, kMaxGeneratedScenePx));
  if (reader.node("disc_diameter_deg") == nullptr)
    reader.fail("disc_diameter_deg", "missing required key (the " +
                                         std::string(spec.generator == SceneGenerator::disc_annulus ? "disc's" : "source's") +
                                         " diameter in degrees of visual angle)");
  spec.disc_diameter_deg =
      reader.number_in_range("disc_diameter_deg", spec.disc_diameter_deg, kMinDiameterDeg, kMaxDiameterDeg, "deg");
  if (reader.node("disc_fraction_of_peak") == nullptr)
    reader.fail("disc_fraction_of_peak", "missing required key (its luminance as a fraction of the display's peak, "
                                         "0 < f <= 1; Spencer 1995's source: 0.75)");
  spec.disc_fraction_of_peak = reader.number_in_range("disc_fraction_of_peak", spec.disc_fraction_of_peak, 0.0, 1.0);
  if (!(spec.disc_fraction_of_peak > 0.0))
    reader.fail("disc_fraction_of_peak", "must be > 0 (a black disc is not a stimulus), found 0");
  const double disc_px = centred_span_px(display, spec.disc_diameter_deg);
  if (spec.generator == SceneGenerator::disc_annulus) {
    if (reader.node("annulus_diameter_deg") == nullptr)
      reader.fail("annulus_diameter_deg", "missing required key (the annulus's outer diameter in degrees)");
    spec.annulus_diameter_deg = reader.number_in_range("annulus_diameter_deg", spec.annulus_diameter_deg,
                                                       kMinDiameterDeg, kMaxDiameterDeg, "deg");
    if (!(spec.annulus_diameter_deg > spec.disc_diameter_deg))
      reader.fail("annulus_diameter_deg", "must be larger than disc_diameter_deg (" +
                                              number_text(spec.disc_diameter_deg) + "), found " +
                                              number_text(spec.annulus_diameter_deg));
    const double annulus_px = centred_span_px(display, spec.annulus_diameter_deg);
    if (annulus_px > spec.size_px)
      reader.fail("annulus_diameter_deg", number_text(spec.annulus_diameter_deg) + " deg is " + number_text(annulus_px) +
                                              " px on this display: wider than the " + std::to_string(spec.size_px) +
                                              " px image (size_px)");
  } else if (disc_px > (spec.generator == SceneGenerator::desk_lamp ? 0.15 : 1.0) * spec.size_px) {
    reader.fail("disc_diameter_deg",
                number_text(spec.disc_diameter_deg) + " deg is " + number_text(disc_px) + " px on this display: " +
                    (spec.generator == SceneGenerator::desk_lamp
                         ? "the bulb must be at most 15 % of the " + std::to_string(spec.size_px) + " px image (size_px)"
                         : "wider than the " + std::to_string(spec.size_px) + " px image (size_px)"));
  }
  if (reader.node("scale_cd_m2") != nullptr)
    reader.fail_at_key("scale_cd_m2", "a generated scene's luminances are fractions of the display's peak "
                                      "(disc_fraction_of_peak); scale_cd_m2 is for scene files");
  if (reader.node("file") != nullptr)
    reader.fail_at_key("file", "a scene is either a file or a generator, not both");
  return spec;
}

toml::table generated_scene_toml(const GeneratedSceneSpec& spec) {
  toml::table table{{"generator", to_string(spec.generator)},
                    {"size_px", spec.size_px},
                    {"disc_diameter_deg", spec.disc_diameter_deg},
                    {"disc_fraction_of_peak", spec.disc_fraction_of_peak}};
  if (spec.generator == SceneGenerator::disc_annulus) table.insert("annulus_diameter_deg", spec.annulus_diameter_deg);
  return table;
}

}  // namespace glarelab
