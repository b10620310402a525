// Tracker building blocks against hand-checked values: clock offset, message decoding, the pupil
// filter (MAD, speed outliers, blinks, gaps), calibration mapping, the simulated tracker's model
// (Ritschel 2009 Eq. 1-2), CSV replay and the logger.
#include <gtest/gtest.h>

#include <msgpack.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/clock.h"
#include "runner/store/result_store.h"
#include "runner/tracker/clock_offset.h"
#include "runner/tracker/pupil_calibration.h"
#include "runner/tracker/pupil_filter.h"
#include "runner/tracker/pupil_labs_client.h"
#include "runner/tracker/replay_tracker.h"
#include "runner/tracker/simulated_tracker.h"
#include "runner/tracker/tracker_logger.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

TEST(TrackerClockOffset, UsesTheFastestRoundTrips) {
  // Device clock = local + 100 s. Fast trips are symmetric; slow ones have an asymmetric delay that
  // biases their midpoint estimate by +-0.05 s and must be ignored.
  std::vector<RoundTrip> trips = {
      {1.000, 101.0005, 1.001},  // rtt 1 ms, offset 100.0000
      {2.000, 102.0010, 2.002},  // rtt 2 ms, offset 100.0000
      {3.000, 103.0004, 3.001},  // rtt 1 ms, offset 99.9999
      {4.000, 104.1500, 4.200},  // rtt 200 ms, offset 100.05
      {5.000, 105.0500, 5.200},  // rtt 200 ms, offset 99.95
  };
  const ClockOffsetEstimate estimate = estimate_clock_offset(trips, 3);
  EXPECT_NEAR(estimate.offset_s, 100.0, 1e-9);  // median of {100.0, 99.9999, 100.0}
  EXPECT_NEAR(estimate.fastest_round_trip_s, 0.001, 1e-12);
  EXPECT_NEAR(estimate.uncertainty_s, 0.001, 1e-12);  // half of the slowest used trip (2 ms)
  EXPECT_EQ(estimate.round_trips, 5u);
  EXPECT_THROW(estimate_clock_offset({}), std::invalid_argument);
}

std::string pack_map(const std::vector<std::pair<std::string, double>>& entries) {
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(static_cast<std::uint32_t>(entries.size()));
  for (const auto& [key, value] : entries) {
    packer.pack(key);
    if (key == "id")
      packer.pack(static_cast<int>(value));
    else
      packer.pack(value);
  }
  return std::string(buffer.data(), buffer.size());
}

TEST(TrackerPupilLabsMessages, DecodesPupilAndRejectsMalformed) {
  const std::string good = pack_map({{"id", 1}, {"timestamp", 12.5}, {"confidence", 0.9}, {"diameter_3d", 3.75}});
  const auto message = decode_pupil_labs_message("pupil.1.3d", good.data(), good.size());
  ASSERT_TRUE(message);
  EXPECT_EQ(message->eye, 1);
  EXPECT_EQ(message->timestamp_s, 12.5);
  EXPECT_EQ(message->diameter_3d_mm, 3.75);
  EXPECT_EQ(message->confidence, 0.9);
  // The id must match the topic's eye; missing fields, out-of-range confidence and garbage fail.
  EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", good.data(), good.size()));
  const std::string no_diameter = pack_map({{"id", 0}, {"timestamp", 1.0}, {"confidence", 0.9}});
  EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", no_diameter.data(), no_diameter.size()));
  const std::string bad_confidence = pack_map({{"id", 0}, {"timestamp", 1.0}, {"confidence", 1.5}, {"diameter_3d", 3}});
  EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", bad_confidence.data(), bad_confidence.size()));
  const std::string garbage = "\xc1\xc1\xc1";
  EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", garbage.data(), garbage.size()));
  EXPECT_FALSE(decode_pupil_labs_message("notify.x", good.data(), good.size()));
}

// Found by fuzz/pupil_labs_fuzzer.cpp: this 74-byte payload declares an array of 0x08008ca2
// elements, which msgpack allocated (4 GB) before finding the message too short. Counts larger
// than the payload can hold are now refused by the unpack limit before any allocation. The
// decoder's answer was already nullopt (the allocation failed or the parse did), so what this test
// can see is that such messages stay refused and that real messages, nested arrays and maps and
// long strings included, still decode under the limit; the allocation bound itself is checked by
// the fuzz target under libFuzzer's malloc limit (scripts/fuzz.sh, docs/HARDENING.md).
TEST(TrackerPupilLabsMessages, RefusesCountsLargerThanTheMessageAndStillDecodesNestedMessages) {
  const char found_bytes[] =
      "\x85\xa5\xa2\x69\x64\x01\x63\xaa\x70\x75\x70\x69\x70\x75\x70\x69\x6c\x2e\x31\x2e\x00\xdd\x08\x00\x8c\xa2"
      "\x69\x64\x01\xa9\x74\x69\x6d\x65\x73\x74\x61\x6d\x70\x64\x5f\x00\x69\x6c\x2e\x31\xef\x0a\x3d\x70\xa3\xd7"
      "\x0a\xab\x2e\x33\x64\x00\x85\x01\x00\x00\x00\x00\x00\x00\x00\x75\x70\x69\x70\x66\x66\x66";
  const std::string found(found_bytes, sizeof found_bytes - 1);  // the literal's bytes, not its NUL
  ASSERT_EQ(found.size(), 74u);
  EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", found.data(), found.size()));
  for (const std::string& huge : {std::string("\xdd\xff\xff\xff\xff", 5), std::string("\xdf\xff\xff\xff\xff", 5),
                                  std::string("\x81\xa1x\xdd\x10\x00\x00\x00", 8),
                                  std::string("\x81\xa1x\xdb\xff\xff\xff\xff", 8)})
    EXPECT_FALSE(decode_pupil_labs_message("pupil.0.3d", huge.data(), huge.size()));

  // A message as Pupil Capture sends it: nested maps, arrays and a long string around the fields.
  msgpack::sbuffer buffer;
  msgpack::packer<msgpack::sbuffer> packer(buffer);
  packer.pack_map(7);
  packer.pack(std::string("topic"));
  packer.pack(std::string("gaze.3d.01."));
  packer.pack(std::string("norm_pos"));
  packer.pack(std::vector<double>{0.25, 0.75});
  packer.pack(std::string("confidence"));
  packer.pack(0.5);
  packer.pack(std::string("timestamp"));
  packer.pack(7.0);
  packer.pack(std::string("gaze_normals_3d"));
  packer.pack(std::map<std::string, std::vector<double>>{{"0", {0.1, 0.2, 0.97}}, {"1", {0.0, 0.1, 0.99}}});
  packer.pack(std::string("base_data"));
  packer.pack(std::vector<std::vector<int>>{{}, {1}, {1, 2, 3}});
  packer.pack(std::string("note"));
  packer.pack(std::string(300, 'x'));
  const auto gaze = decode_pupil_labs_message("gaze.3d.01.", buffer.data(), buffer.size());
  ASSERT_TRUE(gaze);
  EXPECT_EQ(gaze->norm_x, 0.25);
  EXPECT_EQ(gaze->norm_y, 0.75);
  EXPECT_EQ(gaze->timestamp_s, 7.0);
}

TEST(TrackerPupilLabsMessages, ParsesAddresses) {
  EXPECT_EQ(parse_pupil_labs_address("pupil-labs://10.0.0.2:50123").port, 50123);
  EXPECT_EQ(parse_pupil_labs_address("pupil-labs://10.0.0.2").port, 50020);
  EXPECT_EQ(parse_pupil_labs_address("pupil-labs://host:1").host, "host");
  EXPECT_THROW(parse_pupil_labs_address("pupil-labs://host:99999"), TrackerError);
  EXPECT_THROW(parse_pupil_labs_address("pupil://host:1"), TrackerError);
}

TEST(TrackerPupilFilter, MedianAndMadMatchHandValues) {
  EXPECT_EQ(median_of({3, 1, 2}), 2.0);
  EXPECT_EQ(median_of({4, 1, 3, 2}), 2.5);
  // {1, 1, 2, 2, 4, 6, 9}: median 2, deviations {1, 1, 0, 0, 2, 4, 7} -> MAD 1.
  EXPECT_EQ(median_absolute_deviation({1, 1, 2, 2, 4, 6, 9}), 1.0);
}

TrackerSample pupil(double t, double mm, double confidence = 0.95, int eye = 0) {
  TrackerSample sample;
  sample.eye = eye;
  sample.session_time_s = t;
  sample.device_time_s = t;
  sample.pupil_diameter_mm = mm;
  sample.confidence = confidence;
  sample.valid = confidence > 0.0 && mm > 0.0;
  return sample;
}

TEST(TrackerPupilFilter, HoldsThroughBlinksAndRejectsOutliers) {
  PupilFilterSettings settings;
  settings.low_pass_cutoff_hz = 1e6;  // no smoothing: the accepted value passes exactly
  PupilFilter filter(settings);
  const double dt = 1.0 / 120.0;
  int k = 0;
  // 1 s of a slow ramp 4.0 -> 4.5 mm (0.5 mm/s).
  for (; k < 120; ++k) EXPECT_TRUE(filter.add(pupil(k * dt, 4.0 + 0.5 * k * dt)).accepted) << k;
  const double before_blink = filter.model_pupil_mm();
  EXPECT_NEAR(before_blink, 4.0 + 0.5 * 119 * dt, 1e-12);
  // A blink as a tracker reports it: 18 samples (150 ms) of confidence 0, diameter 0.
  for (int i = 0; i < 18; ++i, ++k) {
    const FilteredPupil out = filter.add(pupil(k * dt, 0.0, 0.0));
    EXPECT_FALSE(out.accepted);
    EXPECT_TRUE(out.blink);
    EXPECT_EQ(out.model_pupil_mm, before_blink) << "held, never toward 0";
  }
  // The first samples after the blink (within 50 ms) are still rejected, then accepted again.
  const FilteredPupil reopening = filter.add(pupil(k * dt, 4.6));
  ++k;
  EXPECT_FALSE(reopening.accepted);
  for (int i = 0; i < 6; ++i, ++k) filter.add(pupil(k * dt, 4.6));
  EXPECT_TRUE(filter.add(pupil(k * dt, 4.6)).accepted);
  ++k;
  // A 2 mm jump within one sample (240 mm/s) is a speed outlier; so is a value out of range.
  EXPECT_FALSE(filter.add(pupil(k * dt, 6.6)).accepted);
  ++k;
  EXPECT_FALSE(filter.add(pupil(k * dt, 12.0)).accepted);
  ++k;
  EXPECT_FALSE(filter.add(pupil(k * dt, 4.6, 0.5)).accepted) << "below the 0.6 confidence threshold";
  EXPECT_EQ(filter.model_pupil_mm(), 4.6);
  // The tracker's own blink topic also holds the pupil, even with confident samples.
  filter.add_blink({k * dt, true, 0.9});
  ++k;
  EXPECT_FALSE(filter.add(pupil(k * dt, 2.0)).accepted);
}

// A tracker that reports gaze alone (a headset's OpenXR eye gaze: no pupil, no confidence in one)
// is neither a rejected pupil sample nor a closed eye: between two pupil samples, a run of gaze-only
// samples leaves the filter as it was (the next pupil sample is taken at once, with no blink margin)
// and is counted apart.
TEST(TrackerPupilFilter, GazeOnlySamplesAreNeitherRejectedNorBlinks) {
  PupilFilterSettings settings;
  settings.low_pass_cutoff_hz = 1e6;  // no smoothing: the accepted value passes exactly
  PupilFilter filter(settings);
  const double dt = 1.0 / 120.0;
  int k = 0;
  for (; k < 20; ++k) ASSERT_TRUE(filter.add(pupil(k * dt, 4.0)).accepted) << k;
  for (int i = 0; i < 30; ++i, ++k) {
    TrackerSample gaze = pupil(k * dt, 0.0, 1.0);
    gaze.has_pupil = false;
    gaze.valid = true;  // as the headset's: the runtime located the gaze
    gaze.gaze_x = 0.3;
    gaze.gaze_y = 0.6;
    const FilteredPupil out = filter.add(gaze);
    EXPECT_FALSE(out.accepted);
    EXPECT_FALSE(out.blink) << "gaze alone says nothing of the lid";
    EXPECT_EQ(out.model_pupil_mm, 4.0);
  }
  EXPECT_EQ(filter.rejected(), 0u);
  EXPECT_EQ(filter.gaze_only(), 30u);
  // 30 samples (250 ms) later the next pupil sample is taken at once: no gap opened, no margin.
  EXPECT_TRUE(filter.add(pupil(k * dt, 4.1)).accepted);
  EXPECT_EQ(filter.model_pupil_mm(), 4.1);
  // The same sample with has_pupil left true is a pupil of 0 mm: rejected and counted, as before.
  ++k;
  EXPECT_FALSE(filter.add(pupil(k * dt, 0.0, 1.0)).accepted);
  EXPECT_EQ(filter.rejected(), 1u);
}

TEST(TrackerPupilFilter, LowPassIsFirstOrder) {
  // A step from 4 to 5 mm at 120 Hz through a 4 Hz first-order low-pass reaches 1 - exp(-t / tau).
  PupilFilterSettings settings;
  settings.min_speed_threshold_mm_s = 1e9;  // isolate the low-pass
  PupilFilter filter(settings);
  const double dt = 1.0 / 120.0;
  filter.add(pupil(0.0, 4.0));
  FilteredPupil out;
  for (int k = 1; k <= 12; ++k) out = filter.add(pupil(k * dt, 5.0));
  const double tau_s = 1.0 / (2.0 * 3.141592653589793 * 4.0);
  EXPECT_NEAR(out.model_pupil_mm, 5.0 - std::exp(-12 * dt / tau_s), 1e-12);
}

TEST(TrackerPupilFilter, InterpolatesShortGapsAndHoldsLongOnes) {
  const std::vector<double> t = {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
  const std::vector<std::optional<double>> v = {std::nullopt, 4.0, std::nullopt, 5.0,
                                                std::nullopt, std::nullopt, std::nullopt, 3.0};
  const auto out = interpolate_pupil_gaps(t, v, 0.25);
  // Leading gap takes the first value; 0.1-0.3 (0.2 s) is interpolated; 0.3-0.7 (0.4 s) is held.
  const std::vector<double> expected = {4.0, 4.0, 4.5, 5.0, 5.0, 5.0, 5.0, 3.0};
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(out[i], expected[i], 1e-12) << i;
}

TEST(TrackerPupilCalibration, MapsTheMeasuredRangeOntoTwoToEightMm) {
  std::vector<FilteredPupil> black, white;
  for (double mm : {6.0, 6.4, 6.2}) black.push_back({0.0, 0, true, false, mm, mm});
  for (double mm : {3.0, 3.2, 2.8}) white.push_back({0.0, 0, true, false, mm, mm});
  black.push_back({0.0, 0, false, true, 0.1, 0.1});  // rejected samples do not count
  std::string why;
  const auto range = calibrate_pupil_range(black, white, &why);
  ASSERT_TRUE(range) << why;
  EXPECT_NEAR(range->largest_mm, 6.2, 1e-12);
  EXPECT_NEAR(range->smallest_mm, 3.0, 1e-12);
  EXPECT_NEAR(map_pupil_to_model_range(3.0, *range), 2.0, 1e-12);
  EXPECT_NEAR(map_pupil_to_model_range(6.2, *range), 8.0, 1e-12);
  EXPECT_NEAR(map_pupil_to_model_range(4.6, *range), 5.0, 1e-12);  // the middle maps to the middle
  EXPECT_EQ(map_pupil_to_model_range(9.0, *range), 8.0);
  EXPECT_FALSE(calibrate_pupil_range(white, white, &why));
  EXPECT_NE(why.find("did not respond"), std::string::npos);
}

TEST(TrackerSimulated, ModelMatchesRitschelEquationsAndIsSeeded) {
  // Eq. 2 by hand: L = 1 cd/m2 -> 4.9 - 3 tanh(0.4) = 3.760152...; L = 1000 -> 4.9 - 3 tanh(1.6).
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1.0), 4.9 - 3.0 * 0.37994896225522495, 1e-12);
  EXPECT_NEAR(moon_spencer_pupil_diameter_mm(1000.0), 4.9 - 3.0 * 0.92166855440647690, 1e-12);

  SimulatedTracker a(7), b(7), c(8);
  VirtualClock clock(60.0);
  a.start(clock);
  const TrackerBatch batch = a.poll(10.0);
  EXPECT_EQ(batch.samples.size(), 2u * 1201u) << "120 Hz per eye, t = 0 .. 10 s inclusive";
  int blink_samples = 0;
  for (std::size_t i = 0; i < batch.samples.size(); ++i) {
    const TrackerSample& s = batch.samples[i];
    const auto k = static_cast<std::int64_t>(i / 2);
    EXPECT_EQ(s.pupil_diameter_mm, b.sample(k, s.eye).pupil_diameter_mm) << "same seed, same data";
    if (!s.valid) {
      ++blink_samples;
      EXPECT_EQ(s.pupil_diameter_mm, 0.0);
      EXPECT_EQ(s.confidence, 0.0);
    } else {
      EXPECT_GT(s.pupil_diameter_mm, 1.5);
      EXPECT_LT(s.pupil_diameter_mm, 9.0);
      EXPECT_GE(s.gaze_x, 0.0);
      EXPECT_LE(s.gaze_x, 1.0);
    }
  }
  // The eye model's blinks (one per 60/17 s interval, 0.35 s of lid movement): in 10 s two or three
  // blinks of 41-42 samples per eye (tests/tracker_blink_gaze_test.cpp checks them one by one).
  EXPECT_GE(blink_samples, 2 * 2 * 41);
  EXPECT_LE(blink_samples, 2 * 3 * 42);
  EXPECT_NE(batch.samples[10].pupil_diameter_mm, c.sample(5, 0).pupil_diameter_mm) << "another seed differs";
}

TEST(TrackerReplay, ReadsDocumentedCsvColumns) {
  test::ScratchDir dir;
  const auto path = dir.path() / "track.csv";
  std::ofstream(path) << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid,blink\n"
                         "0,10.0,0.0,4.25,0.5,0.5,0.9,1,\n"
                         "1,10.0,0.0,,,,0.0,0,\n"
                         ",,0.005,,,,0.8,,onset\n"
                         "0,10.01,0.01,4.5,0.25,0.75,0.95,1,\n";
  ReplayTracker replay(read_tracker_csv(path.string()), path.string());
  TrackerBatch first = replay.poll(0.004);
  ASSERT_EQ(first.samples.size(), 2u);
  EXPECT_EQ(first.samples[0].pupil_diameter_mm, 4.25);
  EXPECT_EQ(first.samples[1].pupil_diameter_mm, 0.0);
  EXPECT_FALSE(first.samples[1].has_gaze());
  TrackerBatch second = replay.poll(1.0);
  ASSERT_EQ(second.samples.size(), 1u);
  ASSERT_EQ(second.blinks.size(), 1u);
  EXPECT_TRUE(second.blinks[0].onset);
  EXPECT_EQ(second.samples[0].gaze_y, 0.75);
  std::ofstream(dir.path() / "bad.csv") << "eye,device_time_s,session_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n"
                                           "0,x,0,4,,,1,1\n";
  try {
    read_tracker_csv((dir.path() / "bad.csv").string());
    FAIL();
  } catch (const TrackerError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.csv:2:"), std::string::npos) << error.what();
  }
}

// Found by fuzz/replay_tracker_fuzzer.cpp: an eye of 1e95 was converted to int (undefined
// behaviour). Eyes are 0 or 1 (docs/TRACKERS.md); anything else is refused naming file, line, column.
TEST(TrackerReplay, RefusesAnEyeOtherThanZeroOrOneNamingTheCell) {
  test::ScratchDir dir;
  const std::string header = "session_time_s,eye,device_time_s,pupil_diameter_mm,gaze_x,gaze_y,confidence,valid\n";
  for (const std::string eye : {"1e95", "2", "-1", "0.5", "nan"}) {
    const auto path = dir.path() / "eyes.csv";
    std::ofstream(path) << header << "0.25,1,1.25,5.4,0.2,0.8,0.5,1\n"
                        << "0.5," << eye << ",1.5,5.5,0.1,0.9,1,1\n";
    try {
      read_tracker_csv(path.string());
      ADD_FAILURE() << "eye " << eye << " was accepted";
    } catch (const TrackerError& error) {
      EXPECT_NE(std::string(error.what()).find("eyes.csv:3:5: column 'eye': " + eye + " is not an eye (0 right, 1 left)"),
                std::string::npos)
          << error.what();
    }
  }
}

TEST(TrackerLogger, WritesEverySampleWhileTheMainConnectionCommitsTrials) {
  test::ScratchDir dir;
  const std::string db = (dir.path() / "log.db").string();
  ResultStore store(db);
  SessionRecord session;
  session.experiment = "e";
  session.status = "running";
  session.started_utc = utc_now_iso8601();
  const std::int64_t session_id = store.begin_session(session);
  SimulatedTracker tracker(3);
  VirtualClock clock(60.0);
  tracker.start(clock);
  std::int64_t enqueued = 0;
  {
    TrackerLogger logger(db, session_id, 0.01);
    for (int frame = 1; frame <= 300; ++frame) {
      TrackerBatch batch = tracker.poll(frame / 60.0);
      enqueued += static_cast<std::int64_t>(batch.samples.size());
      logger.enqueue(std::move(batch));
      if (frame % 30 == 0) {  // a trial commit on the other connection, competing for the write lock
        TrialRecord trial;
        trial.session_id = session_id;
        trial.trial_index = frame / 30 - 1;
        trial.procedure = "forced_choice";
        trial.condition = "{}";
        store.commit_trial(trial, {FrameRecord{0, 0.0, 0.0, false, {}}});
      }
    }
    logger.finish();
    EXPECT_EQ(logger.samples_written(), enqueued);
  }
  const RecordedTrack logged = read_tracker_database(db, session_id);
  ASSERT_EQ(static_cast<std::int64_t>(logged.samples.size()), enqueued);
  SimulatedTracker reference(3);
  for (std::size_t i = 0; i < logged.samples.size(); ++i) {
    const TrackerSample expected = reference.sample(static_cast<std::int64_t>(i / 2), static_cast<int>(i % 2));
    ASSERT_EQ(logged.samples[i].pupil_diameter_mm, expected.pupil_diameter_mm) << i;
    ASSERT_EQ(logged.samples[i].session_time_s, expected.session_time_s) << i;
  }
  EXPECT_EQ(store.load_trials(session_id).size(), 10u);
}

}  // namespace
}  // namespace glarelab
