// [observer.refraction], [spectacles.NAME], [observer] spectacles and the "spectacles" column: the
// values as written, plus-cylinder transposition, refusals at their place in the file, and the round
// trip through the resolved configuration.
#include <gtest/gtest.h>

#include <string>

#include "protocols/experiment.h"
#include "protocols/observer_optics_config.h"

namespace glarelab {
namespace {

// Line 1 starts the extra tables; the conditions follow them.
std::string experiment_with(const std::string& tables, const std::string& second_row = "") {
  return tables + "\n[experiment]\nname = \"p\"\n[scenes]\na = { file = \"a.exr\" }\n[procedure]\ntype = \"forced_choice\"\n" +
         "[[conditions.rows]]\nname = \"one\"\nscene_a = \"a\"\nscene_b = \"a\"\n" +
         "[[conditions.rows]]\nname = \"two\"\nscene_a = \"a\"\nscene_b = \"a\"\n" + second_row + "\n";
}

std::string refusal(const std::string& text) {
  try {
    parse_experiment_text(text, "p.toml", "/tmp");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

TEST(ObserverOpticsConfig, NothingStatedIsAnEmmetropeWithoutSpectacles) {
  const Experiment e = parse_experiment_text(experiment_with(""), "p.toml", "/tmp");
  EXPECT_FALSE(e.observer_optics.refraction_stated);
  EXPECT_TRUE(e.observer_optics.spectacles.empty());
  EXPECT_EQ(spectacles_for(e.observer_optics, e.conditions[0]), nullptr);
}

TEST(ObserverOpticsConfig, RefractionAndSpectaclesAsWrittenAndPerCondition) {
  const Experiment e = parse_experiment_text(
      experiment_with("[observer]\nage_years = 62\nspectacles = \"reading\"\n"
                      "[observer.refraction]\nsphere_dioptres = -1.5\ncylinder_dioptres = -0.75\naxis_deg = 180\n"
                      "vertex_distance_mm = 13\naccommodation_amplitude_dioptres = 1.0\n"
                      "[spectacles.reading]\nsphere_dioptres = 1.0\ncylinder_dioptres = -0.75\naxis_deg = 170\n"
                      "refractive_index = 1.6\nabbe_number = 42\nnear_add_dioptres = 0\n"
                      "[spectacles.progressive]\nsphere_dioptres = -1.5\nnear_add_dioptres = 2.5\ndecentration_x_mm = 2\n",
                      "spectacles = \"none\""),
      "p.toml", "/tmp");
  const ObserverOptics& optics = e.observer_optics;
  ASSERT_TRUE(optics.refraction_stated);
  EXPECT_EQ(optics.refraction.prescription.sphere_dioptres, -1.5);
  EXPECT_EQ(optics.refraction.prescription.cylinder_dioptres, -0.75);
  EXPECT_EQ(optics.refraction.prescription.axis_deg, 0.0);  // 180 on a prescription is the horizontal, 0
  EXPECT_EQ(optics.refraction.vertex_distance_mm, 13.0);
  EXPECT_EQ(optics.refraction.accommodation_amplitude_dioptres, 1.0);
  ASSERT_EQ(optics.spectacles.size(), 2u);
  const SpectaclesSettings* one = spectacles_for(optics, e.conditions[0]);
  ASSERT_NE(one, nullptr);
  EXPECT_EQ(one->name, "reading");
  EXPECT_EQ(one->refractive_index, 1.6);
  EXPECT_EQ(one->abbe_number, 42.0);
  EXPECT_EQ(one->prescription.axis_deg, 170.0);
  EXPECT_EQ(spectacles_for(optics, e.conditions[1]), nullptr);  // the row's "none"
  const SpectaclesSettings* progressive = optics.find_spectacles("progressive");
  ASSERT_NE(progressive, nullptr);
  EXPECT_EQ(progressive->near_add_dioptres, 2.5);
  EXPECT_EQ(progressive->decentration_x_mm, 2.0);
  EXPECT_EQ(progressive->refractive_index, 1.498);  // CR-39 by default
  EXPECT_EQ(progressive->vertex_distance_mm, 12.0);
}

TEST(ObserverOpticsConfig, PlusCylinderIsTransposedOnlyWhenTheTableSaysSo) {
  const Experiment e = parse_experiment_text(
      experiment_with("[observer.refraction]\nsphere_dioptres = -2.0\ncylinder_dioptres = 1.0\naxis_deg = 100\n"
                      "cylinder_form = \"plus\"\n"),
      "p.toml", "/tmp");
  // -2.00 / +1.00 x 100 is -1.00 / -1.00 x 10.
  EXPECT_EQ(e.observer_optics.refraction.prescription.sphere_dioptres, -1.0);
  EXPECT_EQ(e.observer_optics.refraction.prescription.cylinder_dioptres, -1.0);
  EXPECT_EQ(e.observer_optics.refraction.prescription.axis_deg, 10.0);

  const std::string positive =
      refusal(experiment_with("[observer.refraction]\nsphere_dioptres = -2.0\ncylinder_dioptres = 1.0\naxis_deg = 100\n"));
  EXPECT_NE(positive.find("p.toml:3:21"), std::string::npos) << positive;
  EXPECT_NE(positive.find("observer.refraction.cylinder_dioptres"), std::string::npos) << positive;
  EXPECT_NE(positive.find("(-1 / -1 x 10)"), std::string::npos) << positive;  // the transposed form, to copy
}

TEST(ObserverOpticsConfig, RefusalsNameTheFilePlaceAndKey) {
  const std::string axis = refusal(experiment_with("[observer.refraction]\nsphere_dioptres = -1\naxis_deg = 181\n"));
  EXPECT_NE(axis.find("p.toml:3:12"), std::string::npos) << axis;
  EXPECT_NE(axis.find("observer.refraction.axis_deg"), std::string::npos) << axis;

  const std::string index = refusal(experiment_with("[spectacles.cheap]\nsphere_dioptres = 1\nrefractive_index = 0.9\n"));
  EXPECT_NE(index.find("p.toml:3:20"), std::string::npos) << index;
  EXPECT_NE(index.find("spectacles.cheap.refractive_index"), std::string::npos) << index;

  const std::string air = refusal(experiment_with("[spectacles.cheap]\nrefractive_index = 1.0\n"));
  EXPECT_NE(air.find("must be > 1"), std::string::npos) << air;

  const std::string abbe = refusal(experiment_with("[spectacles.cheap]\nabbe_number = 0\n"));
  EXPECT_NE(abbe.find("spectacles.cheap.abbe_number"), std::string::npos) << abbe;

  const std::string vertex = refusal(experiment_with("[observer.refraction]\nvertex_distance_mm = 0\n"));
  EXPECT_NE(vertex.find("in front of the cornea"), std::string::npos) << vertex;

  const std::string unknown = refusal(experiment_with("[spectacles.cheap]\nsphere = 1\n"));
  EXPECT_NE(unknown.find("spectacles.cheap.sphere"), std::string::npos) << unknown;

  const std::string unknown_refraction = refusal(experiment_with("[observer.refraction]\ncyl = -1\n"));
  EXPECT_NE(unknown_refraction.find("observer.refraction.cyl"), std::string::npos) << unknown_refraction;

  const std::string worn = refusal(experiment_with("[observer]\nspectacles = \"distance\"\n"));
  EXPECT_NE(worn.find("observer.spectacles"), std::string::npos) << worn;
  EXPECT_NE(worn.find("no [spectacles.distance] table"), std::string::npos) << worn;

  const std::string column = refusal(experiment_with("[spectacles.reading]\nsphere_dioptres = 2\n", "spectacles = \"readng\""));
  EXPECT_NE(column.find("condition 'two' spectacles"), std::string::npos) << column;

  const std::string none = refusal(experiment_with("[spectacles.none]\nsphere_dioptres = 2\n"));
  EXPECT_NE(none.find("'none' means no spectacles"), std::string::npos) << none;
}

TEST(ObserverOpticsConfig, ResolvedConfigurationReadsBackTheSame) {
  const Experiment e = parse_experiment_text(
      experiment_with("[observer]\nspectacles = \"reading\"\n"
                      "[observer.refraction]\nsphere_dioptres = 0.5\ncylinder_dioptres = 1.0\naxis_deg = 45\ncylinder_form = \"plus\"\n"
                      "[spectacles.reading]\nsphere_dioptres = 2.25\ncylinder_dioptres = -0.5\naxis_deg = 30\nabbe_number = 36\n"),
      "p.toml", "/tmp");
  const Experiment again = parse_experiment_text(resolved_config_toml(e), "resolved.toml", "/tmp");
  const ObserverOptics& a = e.observer_optics;
  const ObserverOptics& b = again.observer_optics;
  EXPECT_EQ(b.refraction_stated, a.refraction_stated);
  EXPECT_EQ(b.refraction.prescription.sphere_dioptres, a.refraction.prescription.sphere_dioptres);
  EXPECT_EQ(b.refraction.prescription.cylinder_dioptres, a.refraction.prescription.cylinder_dioptres);
  EXPECT_EQ(b.refraction.prescription.axis_deg, a.refraction.prescription.axis_deg);
  EXPECT_EQ(b.refraction.accommodation_amplitude_dioptres, a.refraction.accommodation_amplitude_dioptres);
  EXPECT_EQ(b.spectacles_worn, "reading");
  ASSERT_EQ(b.spectacles.size(), 1u);
  EXPECT_EQ(b.spectacles[0].abbe_number, 36.0);
  EXPECT_EQ(b.spectacles[0].prescription.sphere_dioptres, 2.25);
}

}  // namespace
}  // namespace glarelab
