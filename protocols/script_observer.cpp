// An observer that reads its answers from a text file: reproducible end-to-end runs, and tests of
// what a session records for known answers.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "protocols/observer.h"

namespace glarelab {
namespace {

struct ScriptEntry {
  std::string text;
  SourceLocation where;
};

class ScriptObserver : public Observer {
 public:
  ScriptObserver(std::string path, std::vector<ScriptEntry> entries, bool timeout_allowed)
      : path_(std::move(path)), entries_(std::move(entries)), timeout_allowed_(timeout_allowed) {}

  std::string description() const override { return "script:" + path_; }

  Response respond(const TrialPlan& plan) override {
    // Entry k answers trial k, not "the next unread line": a session resumed at trial 7 gets
    // entry 7, exactly what the uninterrupted session would have got.
    if (plan.trial_index < 0 || static_cast<std::size_t>(plan.trial_index) >= entries_.size()) {
      // Bad input (exit 2), at the end of the script: the line the missing answer belongs on.
      const int end_line = entries_.empty() ? 1 : entries_.back().where.line + 1;
      throw ConfigError(SourceLocation{path_, end_line, 0}, "",
                        "response script holds " + std::to_string(entries_.size()) + " responses; trial " +
                            std::to_string(plan.trial_index) + " needs response " +
                            std::to_string(plan.trial_index + 1));
    }
    const ScriptEntry& entry = entries_[static_cast<std::size_t>(plan.trial_index)];
    const std::vector<std::string>& allowed = plan.allowed_responses;
    Response response;
    if (std::find(allowed.begin(), allowed.end(), entry.text) != allowed.end() || entry.text == "abort" ||
        (timeout_allowed_ && entry.text == kTimeoutResponse)) {
      // A named response, "abort" to end the session as an observer pressing Escape would, or
      // "timeout": no answer within the response window.
      response.value = entry.text;
    } else if (!allowed.empty() && (entry.text == "1" || entry.text == "0")) {
      // "1" answers correctly and "0" incorrectly. Without a correct answer (equal sources) "1"
      // is the first allowed response and "0" the other one, so scripts stay deterministic.
      const std::string& right = plan.correct_response.empty() ? allowed.front() : plan.correct_response;
      if (entry.text == "1") {
        response.value = right;
      } else {
        const auto other = std::find_if(allowed.begin(), allowed.end(), [&](const std::string& r) { return r != right; });
        if (other == allowed.end()) throw not_allowed(entry, allowed);
        response.value = *other;
      }
    } else if (allowed.empty() && is_numbers(entry.text)) {
      // Procedures without named responses (adjustment: "L R" or one value for both spots) take
      // the numbers as written.
      response.value = entry.text;
    } else {
      throw not_allowed(entry, allowed);
    }
    return response;
  }

 private:
  // One or two numbers separated by blanks.
  static bool is_numbers(const std::string& text) {
    std::size_t start = 0;
    int count = 0;
    while (start < text.size()) {
      const std::size_t end = std::min(text.find(' ', start), text.size());
      if (end > start) {
        try {
          const std::string token = text.substr(start, end - start);
          std::size_t used = 0;
          (void)std::stod(token, &used);
          if (used != token.size()) return false;
        } catch (const std::exception&) {
          return false;
        }
        ++count;
      }
      start = end + 1;
    }
    return count == 1 || count == 2;
  }

  ConfigError not_allowed(const ScriptEntry& entry, const std::vector<std::string>& allowed) const {
    std::string names = "'1', '0'";
    for (const std::string& name : allowed) names += ", '" + name + "'";
    if (timeout_allowed_) names += ", 'timeout'";
    return ConfigError(entry.where, "", "response '" + entry.text + "' is not allowed (allowed: " + names + ", 'abort')");
  }

  std::string path_;
  std::vector<ScriptEntry> entries_;
  bool timeout_allowed_;
};

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

}  // namespace

std::unique_ptr<Observer> make_script_observer(const std::string& path, bool timeout_allowed) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_regular_file(path, error)) throw ConfigError(SourceLocation{path, 0, 0}, "", "response script: file not found");
  std::ifstream in(path, std::ios::binary);
  if (!in.is_open()) throw ConfigError(SourceLocation{path, 0, 0}, "", "response script: cannot be opened");
  const std::string absolute = fs::absolute(fs::path(path)).lexically_normal().string();

  std::vector<ScriptEntry> entries;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const int column = static_cast<int>(line.find_first_not_of(" \t")) + 1;
    entries.push_back({text, SourceLocation{absolute, number, column}});
  }
  return std::make_unique<ScriptObserver>(absolute, std::move(entries), timeout_allowed);
}

}  // namespace glarelab
