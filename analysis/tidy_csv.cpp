#include "analysis/tidy_csv.h"

#include <atomic>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string_view>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace glarelab::analysis {
namespace {

// A CSV file written beside its name and renamed into place when complete (core/atomic_file.h),
// with the permission bits `mode` (the database's) when given.
class CsvFile {
 public:
  CsvFile(const std::string& path, std::optional<unsigned> mode) : file_(path, mode) {}
  void row(const std::vector<std::string>& fields) {
    std::ostream& out = file_.stream();
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (i > 0) out << ',';
      out << csv_field(fields[i]);
    }
    out << "\r\n";  // RFC 4180 line ends
  }
  void close() { file_.commit(); }

 private:
  AtomicFile file_;
};

std::string optional_number(const std::optional<double>& value) { return value ? csv_number(*value) : std::string(); }
std::string optional_int(const std::optional<int>& value) { return value ? std::to_string(*value) : std::string(); }

}  // namespace

namespace {
std::atomic<bool> formula_cells_raw{false};

// A cell a spreadsheet would run as a formula (OWASP "CSV injection"): text starting with = + - @,
// or with a tab or carriage return before one. A number (-0.5, +3, -inf) is a number, not a formula.
bool reads_as_formula(const std::string& value) {
  if (value.empty() || std::string_view("=+-@\t\r").find(value.front()) == std::string_view::npos) return false;
  char* end = nullptr;
  std::strtod(value.c_str(), &end);
  return end != value.c_str() + value.size();
}
}  // namespace

void keep_formula_cells_raw(bool raw) { formula_cells_raw = raw; }

std::string csv_field(const std::string& text) {
  // A leading apostrophe makes a spreadsheet show the cell as text (and is visible, so a reader
  // sees that the cell was changed); --raw-csv-cells keeps cells as stored.
  const std::string value = !formula_cells_raw && reads_as_formula(text) ? "'" + text : text;
  const bool needs_quotes = value.find_first_of(",\"\r\n") != std::string::npos ||
                            (!value.empty() && (value.front() == ' ' || value.back() == ' '));
  if (!needs_quotes) return value;
  std::string quoted = "\"";
  for (char c : value) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// std::to_chars without a format gives the shortest text that reads back to the same double (C++17
// [charconv]), without the trial snprintf/strtod round trips that dominated writing a million-row
// frames.csv.
std::string csv_number(double value) {
  char text[40];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

std::string condition_column(const std::string& key) {
  std::string name = "condition_";
  for (char c : key) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    name += plain ? c : '_';
  }
  return name;
}

std::vector<std::string> write_tidy_csv(const LoadedData& data, const std::string& directory,
                                        std::optional<unsigned> mode) {
  std::filesystem::create_directories(directory);
  const std::filesystem::path dir(directory);
  std::vector<std::string> written;

  // Condition keys in first-seen order over all trials; each becomes a column.
  std::vector<std::string> keys;
  std::set<std::string> seen;
  bool any_adjustments = false;
  for (const LoadedSession& session : data.sessions) {
    for (const LoadedTrial& trial : session.trials) {
      any_adjustments = any_adjustments || !trial.adjustments.empty();
      for (const auto& field : trial.condition) {
        if (seen.insert(field.first).second) keys.push_back(field.first);
      }
    }
  }

  {
    const std::string path = (dir / "trials.csv").string();
    CsvFile file(path, mode);
    std::vector<std::string> header = {"database", "session_id", "participant", "experiment", "session_status",
                                       "trial_id", "trial_index", "block", "procedure", "condition"};
    std::set<std::string> used(header.begin(), header.end());
    for (const std::string& key : keys) {
      std::string column = condition_column(key);
      while (!used.insert(column).second) column += "_";  // keys that differ only in odd characters
      header.push_back(column);
    }
    for (const char* column : {"intensity", "response", "correct", "response_time_s", "onset_s", "staircase",
                               "reversal", "adjustment_mean"}) {
      header.emplace_back(column);
    }
    file.row(header);
    for (const LoadedSession& session : data.sessions) {
      for (const LoadedTrial& trial : session.trials) {
        const TrialRecord& r = trial.record;
        std::vector<std::string> row = {session.database, std::to_string(session.record.id), session.record.participant,
                                        session.record.experiment, session.record.status, std::to_string(r.id),
                                        std::to_string(r.trial_index), std::to_string(r.block), r.procedure,
                                        r.condition};
        // Looked up by hash: a condition of 200k keys made the linear lookup quadratic.
        std::unordered_map<std::string_view, const std::string*> values;
        values.reserve(trial.condition.size());
        for (const auto& [key, value] : trial.condition) values.try_emplace(key, &value);
        for (const std::string& key : keys) {
          const auto found = values.find(key);
          row.push_back(found != values.end() ? *found->second : std::string());
        }
        std::string adjustment_mean;
        if (!trial.adjustments.empty()) {
          double sum = 0.0;
          for (const AdjustmentRecord& a : trial.adjustments) sum += a.value;
          adjustment_mean = csv_number(sum / static_cast<double>(trial.adjustments.size()));
        }
        for (std::string value : {optional_number(r.intensity), r.response, optional_int(r.correct),
                                  optional_number(r.response_time_s), csv_number(r.onset_s), r.staircase,
                                  optional_int(r.reversal), adjustment_mean}) {
          row.push_back(std::move(value));
        }
        file.row(row);
      }
    }
    file.close();
    written.push_back(path);
  }
  {
    const std::string path = (dir / "frames.csv").string();
    CsvFile file(path, mode);
    file.row({"database", "session_id", "trial_id", "trial_index", "frame_index", "scheduled_s", "flip_s", "dropped",
              "gaze_age_s"});
    for (const LoadedSession& session : data.sessions) {
      const std::string session_id = std::to_string(session.record.id);
      for (const LoadedTrial& trial : session.trials) {
        const std::string trial_id = std::to_string(trial.record.id);
        const std::string trial_index = std::to_string(trial.record.trial_index);
        for (const FrameRecord& frame : trial.frames) {
          file.row({session.database, session_id, trial_id, trial_index, std::to_string(frame.frame_index),
                    csv_number(frame.scheduled_s), csv_number(frame.flip_s), frame.dropped ? "1" : "0",
                    optional_number(frame.gaze_age_s)});
        }
      }
    }
    file.close();
    written.push_back(path);
  }
  {
    const std::string path = (dir / "tracker_samples.csv").string();
    CsvFile file(path, mode);
    file.row({"database", "session_id", "eye", "device_time_s", "session_time_s", "pupil_diameter_mm", "gaze_x",
              "gaze_y", "confidence", "valid"});
    for (const LoadedSession& session : data.sessions) {
      const std::string session_id = std::to_string(session.record.id);
      for (const TrackerSampleRecord& s : session.tracker_samples) {
        file.row({session.database, session_id, std::to_string(s.eye), csv_number(s.device_time_s),
                  csv_number(s.session_time_s), optional_number(s.pupil_diameter_mm), optional_number(s.gaze_x),
                  optional_number(s.gaze_y), csv_number(s.confidence), s.valid ? "1" : "0"});
      }
    }
    file.close();
    written.push_back(path);
  }
  if (any_adjustments) {
    const std::string path = (dir / "adjustments.csv").string();
    CsvFile file(path, mode);
    file.row({"database", "session_id", "trial_id", "spot", "value"});
    for (const LoadedSession& session : data.sessions) {
      for (const LoadedTrial& trial : session.trials) {
        for (const AdjustmentRecord& a : trial.adjustments) {
          file.row({session.database, std::to_string(session.record.id), std::to_string(trial.record.id),
                    std::to_string(a.spot), csv_number(a.value)});
        }
      }
    }
    file.close();
    written.push_back(path);
  }
  return written;
}

}  // namespace glarelab::analysis
