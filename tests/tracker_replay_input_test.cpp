// Replay input that cannot be a recording is refused with the file, line, column and what the
// column can hold, instead of being stored as if a tracker had measured it.
#include <gtest/gtest.h>

#include <string>

#include "runner/store/result_store.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/tracker_source.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

const std::string kHeader = "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";

std::string error_of(const std::string& path) {
  try {
    read_tracker_csv(path);
  } catch (const TrackerError& error) {
    return error.what();
  }
  return "no error";
}

TEST(TrackerReplayInput, ValuesNoTrackerReportsAreRefusedAtTheirCell) {
  test::ScratchDir dir;
  const auto check = [&](const std::string& row, const std::string& expected) {
    const std::string path = dir.write("track.csv", kHeader + "0,1.0,1.0,4.0,0.5,0.5,0.9,1\n" + row + "\n");
    EXPECT_EQ(error_of(path), path + expected) << row;
  };
  check("7,1.1,1.1,4.0,0.5,0.5,0.9,1", ":3:1: column 'eye': 7 is not an eye (0 right, 1 left)");
  check("1,1.1,1.1,4.0,0.5,0.5,9,1", ":3:23: column 'confidence': 9 is not a confidence from 0 to 1");
  check("1,1.1,1.1,4.0,0.5,0.5,0.9,3", ":3:27: column 'valid': 3 is not 0 or 1");
  check("1,1.1,1.1,-2,0.5,0.5,0.9,1", ":3:11: column 'pupil_diameter_mm': -2 is not a pupil diameter from 0 to 20 mm");
  check("1,inf,1.1,4.0,0.5,0.5,0.9,1", ":3:3: column 'device_time_s': inf is not a finite time");
  // A well-formed recording reads back as written.
  const std::string good = dir.write("good.csv", kHeader + "0,1.0,1.5,4.0,0.25,0.75,0.9,1\n1,1.0,1.5,,,,0,0\n");
  const RecordedTrack track = read_tracker_csv(good);
  ASSERT_EQ(track.samples.size(), 2u);
  EXPECT_EQ(track.samples[0].eye, 0);
  EXPECT_EQ(track.samples[0].session_time_s, 1.5);
  EXPECT_EQ(track.samples[0].gaze_y, 0.75);
  EXPECT_EQ(track.samples[1].eye, 1);
  EXPECT_FALSE(track.samples[1].valid);
}

TEST(TrackerReplayInput, AMissingFileIsCalledAReplayFileAndADatabaseNeedsItsSession) {
  test::ScratchDir dir;
  const std::string missing = (dir.path() / "absent.csv").string();
  EXPECT_EQ(error_of(missing), "tracker replay: " + missing + ": file not found");

  const std::string db = (dir.path() / "earlier.db").string();
  { const ResultStore store(db); }
  try {
    make_tracker_source("replay:" + db, 1);
    FAIL() << "a database without #SESSION was accepted";
  } catch (const TrackerError& error) {
    EXPECT_EQ(std::string(error.what()), "--tracker replay:" + db + ": " + db +
                                             " is a results database: name the session to replay, "
                                             "replay:FILE.db#SESSION");
  }
}

}  // namespace
}  // namespace glarelab
