#include "runner/tracker/replay_tracker.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/database_wait.h"
#include "protocols/csv_table.h"

namespace glarelab {

namespace {

double parse_number(const CsvCell& cell, const std::string& file, const std::string& column) {
  char* end = nullptr;
  const double value = std::strtod(cell.text.c_str(), &end);
  if (cell.text.empty() || end != cell.text.c_str() + cell.text.size())
    throw TrackerError(file + ":" + std::to_string(cell.where.line) + ":" + std::to_string(cell.where.column) +
                       ": column '" + column + "': '" + cell.text + "' is not a number");
  return value;
}

// Refuses a value outside what the column can hold (the DATABASE.md meaning of tracker_samples):
// a recorded track with eye 7 or confidence 9 would be stored as if it were real.
double checked(double value, const CsvCell& cell, const std::string& file, const std::string& column, bool ok,
               const std::string& expected) {
  if (!ok || !std::isfinite(value))
    throw TrackerError(file + ":" + std::to_string(cell.where.line) + ":" + std::to_string(cell.where.column) +
                       ": column '" + column + "': " + cell.text + " is not " + expected);
  return value;
}

}  // namespace

RecordedTrack read_tracker_csv(const std::string& path) {
  std::error_code missing;
  if (!std::filesystem::is_regular_file(path, missing))
    throw TrackerError("tracker replay: " + path + ": file not found");
  CsvTable table;
  try {
    table = read_csv_file(path, {"--tracker replay:" + path, 0, 0});
  } catch (const std::exception& error) {
    throw TrackerError(std::string("tracker replay: ") + error.what());
  }
  const char* columns[] = {"eye", "device_time_s", "session_time_s", "pupil_diameter_mm", "gaze_x", "gaze_y",
                           "confidence", "valid"};
  std::vector<int> index;
  for (const char* name : columns) {
    const int column = table.column(name);
    if (column < 0) throw TrackerError(path + ":1: tracker replay: missing column '" + std::string(name) + "'");
    index.push_back(column);
  }
  const int blink_column = table.column("blink");
  RecordedTrack track;
  for (const auto& row : table.rows) {
    auto cell = [&](std::size_t i) -> const CsvCell& { return row[static_cast<std::size_t>(index[i])]; };
    auto number = [&](std::size_t i) { return parse_number(cell(i), path, columns[i]); };
    if (blink_column >= 0 && !row[static_cast<std::size_t>(blink_column)].text.empty()) {
      const CsvCell& kind = row[static_cast<std::size_t>(blink_column)];
      if (kind.text != "onset" && kind.text != "offset")
        throw TrackerError(path + ":" + std::to_string(kind.where.line) + ": column 'blink': '" + kind.text +
                           "' (expected onset or offset)");
      track.blinks.push_back({number(2), kind.text == "onset", number(6)});
      continue;
    }
    const auto check = [&](std::size_t i, double value, bool ok, const std::string& expected) {
      return checked(value, cell(i), path, columns[i], ok, expected);
    };
    TrackerSample sample;
    // Checked before the conversion to int, which is undefined for numbers outside int's range
    // (a typo such as 1e95 in the file).
    const double eye = number(0);
    sample.eye = static_cast<int>(check(0, eye, eye == 0.0 || eye == 1.0, "an eye (0 right, 1 left)"));
    sample.device_time_s = check(1, number(1), true, "a finite time");
    sample.session_time_s = check(2, number(2), true, "a finite time");
    if (!cell(3).text.empty()) {
      const double pupil = number(3);
      sample.pupil_diameter_mm = check(3, pupil, pupil >= 0.0 && pupil <= 20.0, "a pupil diameter from 0 to 20 mm");
    }
    sample.gaze_x = cell(4).text.empty() ? -1.0 : check(4, number(4), true, "a finite gaze coordinate");
    sample.gaze_y = cell(5).text.empty() ? -1.0 : check(5, number(5), true, "a finite gaze coordinate");
    const double confidence = number(6);
    sample.confidence = check(6, confidence, confidence >= 0.0 && confidence <= 1.0, "a confidence from 0 to 1");
    const double valid = number(7);
    sample.valid = check(7, valid, valid == 0.0 || valid == 1.0, "0 or 1") != 0.0;
    track.samples.push_back(sample);
  }
  std::stable_sort(track.blinks.begin(), track.blinks.end(),
                   [](const BlinkEvent& a, const BlinkEvent& b) { return a.session_time_s < b.session_time_s; });
  return track;
}

RecordedTrack read_tracker_database(const std::string& path, std::int64_t session_id) {
  sqlite3* db = nullptr;
  auto fail = [&](const std::string& what) -> TrackerError {
    const std::string message = db != nullptr ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close_v2(db);
    return TrackerError("tracker replay: SQLite: " + path + ": " + what + ": " + message);
  };
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) throw fail("opening");
  sqlite3_busy_timeout(db, kDatabaseBusyTimeoutMs);
  RecordedTrack track;
  sqlite3_stmt* statement = nullptr;
  const char* samples_sql =
      "SELECT eye, device_time_s, session_time_s, pupil_diameter_mm, gaze_x, gaze_y, confidence, valid "
      "FROM tracker_samples WHERE session_id = ?1 ORDER BY rowid";
  if (sqlite3_prepare_v2(db, samples_sql, -1, &statement, nullptr) != SQLITE_OK) throw fail("reading tracker_samples");
  sqlite3_bind_int64(statement, 1, session_id);
  while (sqlite3_step(statement) == SQLITE_ROW) {
    TrackerSample sample;
    sample.eye = sqlite3_column_int(statement, 0);
    sample.device_time_s = sqlite3_column_double(statement, 1);
    sample.session_time_s = sqlite3_column_double(statement, 2);
    auto optional = [&](int column, double missing) {
      return sqlite3_column_type(statement, column) == SQLITE_NULL ? missing : sqlite3_column_double(statement, column);
    };
    sample.pupil_diameter_mm = optional(3, 0.0);
    sample.gaze_x = optional(4, -1.0);
    sample.gaze_y = optional(5, -1.0);
    sample.confidence = sqlite3_column_double(statement, 6);
    sample.valid = sqlite3_column_int(statement, 7) != 0;
    track.samples.push_back(sample);
  }
  sqlite3_finalize(statement);
  const char* blinks_sql =
      "SELECT session_time_s, kind FROM session_events WHERE session_id = ?1 AND kind IN ('blink_onset', "
      "'blink_offset') ORDER BY session_time_s, id";
  if (sqlite3_prepare_v2(db, blinks_sql, -1, &statement, nullptr) != SQLITE_OK) throw fail("reading session_events");
  sqlite3_bind_int64(statement, 1, session_id);
  while (sqlite3_step(statement) == SQLITE_ROW) {
    const std::string kind = reinterpret_cast<const char*>(sqlite3_column_text(statement, 1));
    track.blinks.push_back({sqlite3_column_double(statement, 0), kind == "blink_onset", 0.0});
  }
  sqlite3_finalize(statement);
  sqlite3_close_v2(db);
  if (track.samples.empty())
    throw TrackerError("tracker replay: " + path + ": session " + std::to_string(session_id) +
                       " has no tracker samples");
  return track;
}

ReplayTracker::ReplayTracker(RecordedTrack track, std::string origin)
    : track_(std::move(track)), origin_(std::move(origin)) {}

TrackerBatch ReplayTracker::poll(double now_s) {
  TrackerBatch batch;
  while (next_sample_ < track_.samples.size() && track_.samples[next_sample_].session_time_s <= now_s)
    batch.samples.push_back(track_.samples[next_sample_++]);
  while (next_blink_ < track_.blinks.size() && track_.blinks[next_blink_].session_time_s <= now_s)
    batch.blinks.push_back(track_.blinks[next_blink_++]);
  status_.samples += static_cast<std::int64_t>(batch.samples.size());
  return batch;
}

}  // namespace glarelab
