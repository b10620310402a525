// The observer's eye a session stored (analysis/session_observer_eye.h): read back from the
// configuration the session writes (protocols' resolved experiment), shown in the report's
// sessions table, and "not stored" for configurations from before the keys existed.
#include <gtest/gtest.h>

#include "analysis/analysis_report.h"
#include "analysis/report_output.h"
#include "analysis/session_observer_eye.h"
#include "protocols/experiment.h"
#include "tests/analysis_synthetic.h"
#include "tests/scratch_dir.h"

namespace glarelab::analysis {
namespace {

std::string stored_config(const std::string& observer_table) {
  const Experiment experiment = parse_experiment_text(
      "[experiment]\nname = \"eye\"\n[scenes]\na = { file = \"/a.exr\" }\nb = { file = \"/b.exr\" }\n"
      "[procedure]\ntype = \"forced_choice\"\n[conditions]\nrows = [ { scene_a = \"a\", scene_b = \"b\" } ]\n" +
          observer_table,
      "mem.toml", "/");
  return resolved_config_toml(experiment);
}

TEST(SessionObserverEye, ReadsTheEyeTheSessionStored) {
  const auto eye = stored_observer_eye(stored_config("[observer]\nage_years = 64.5\npigmentation = 0.25\n"));
  ASSERT_TRUE(eye.has_value());
  EXPECT_EQ(eye->age_years, 64.5);
  EXPECT_EQ(eye->pigmentation, 0.25);
  EXPECT_EQ(observer_eye_text(stored_config("")), "25 years, pigmentation 0.5");  // the defaults are stored
  // Older sessions (no keys), and text that is not TOML.
  EXPECT_FALSE(stored_observer_eye("[experiment]\nname = \"old\"\n[observer.simulated]\nslope = 2\n").has_value());
  EXPECT_FALSE(stored_observer_eye("[observer\nage_years = ").has_value());
  EXPECT_EQ(observer_eye_text("[experiment]\nname = \"old\"\n"), "not stored");
}

TEST(SessionObserverEye, ShownInTheReportsSessionsTable) {
  const test::ScratchDir dir;
  const std::string path = dir.file("eye.db");
  {
    ResultStore store(path);
    SessionRecord session = test::synthetic_session("P1");
    session.config = stored_config("[observer]\nage_years = 71\npigmentation = 0.9\n");
    const auto id = store.begin_session(session);
    test::commit_trials(store, id, {test::preference_trial("Gem", "brighter", true, "dynamic")});
    store.finish_session(id, "completed");
    const auto old = store.begin_session(test::synthetic_session("P2"));
    store.finish_session(old, "completed");
  }
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  const std::string html = render_html(analyse(load_databases({path}), options));
  EXPECT_NE(html.find("<th>observer's eye</th>"), std::string::npos) << html.substr(0, 2000);
  EXPECT_NE(html.find("71 years, pigmentation 0.9"), std::string::npos);
  EXPECT_NE(html.find("not stored"), std::string::npos);
}

}  // namespace
}  // namespace glarelab::analysis
