#include "runner/session/status_line.h"

#include "core/text_limits.h"

#include <unistd.h>

#include <cmath>
#include <sstream>

namespace glarelab {
namespace {

// Erase the terminal's current line: carriage return, then ECMA-48 EL (erase to the line's end).
constexpr const char* kClearLine = "\r\033[K";
// The terminal line is redrawn this often: twice within the 2 s a reader waits at most.
constexpr auto kRedrawPeriod = std::chrono::seconds(1);
// Plain lines (not a terminal) at most this often.
constexpr auto kPlainLinePeriod = std::chrono::seconds(2);

std::string seconds_text(double seconds) {
  std::ostringstream text;
  if (seconds < 60.0) {
    text << static_cast<long>(std::lround(seconds)) << " s";
  } else {
    const long whole = std::lround(seconds);
    text << whole / 60 << " min " << whole % 60 << " s";
  }
  return text.str();
}

}  // namespace

StatusLine::StatusLine(std::ostream& out, bool terminal)
    : out_(out), terminal_(terminal), buffer_(*this), stream_(&buffer_) {
  if (!terminal_) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    draw_locked();
  }
  ticker_ = std::thread([this] { tick(); });
}

StatusLine::~StatusLine() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
  if (terminal_) out_ << kClearLine << std::flush;
}

bool StatusLine::stdout_is_terminal() { return ::isatty(STDOUT_FILENO) == 1; }

void StatusLine::tick() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, kRedrawPeriod, [this] { return stopping_; });
    if (!stopping_) draw_locked();
  }
}

void StatusLine::set_step(const std::string& step) {
  const std::lock_guard<std::mutex> lock(mutex_);
  step_ = step;
  // Plain lines begin with the trials: the steps before them (loading, opening the display) come
  // before the input is fully checked, and a refused file's error is then the only thing printed,
  // as `validate` prints it. On a terminal the line is redrawn in place and cleared before errors.
  if (terminal_) changed_locked();
}

void StatusLine::set_trial(int number, int total, const std::string& block) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (trial_ == 0) first_trial_ = Clock::now();
  trial_ = number;
  total_ = total;
  block_ = block;
  detail_.clear();
  changed_locked();
}

void StatusLine::set_detail(const std::string& detail) {
  const std::lock_guard<std::mutex> lock(mutex_);
  detail_ = detail;
  if (!detail.empty()) changed_locked();
}

std::string StatusLine::text() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return text_locked();
}

std::string StatusLine::text_locked() const {
  const Clock::time_point now = Clock::now();
  std::ostringstream text;
  if (trial_ == 0) {
    text << step_;
  } else {
    text << "trial " << trial_ << " of " << total_;
    if (!block_.empty()) text << ", " << block_;
  }
  text << ": " << seconds_text(std::chrono::duration<double>(now - start_).count()) << " elapsed";
  // The trials since the first took this long each on average; as long again for each one left.
  if (trial_ > 1 && total_ >= trial_) {
    const double per_trial_s = std::chrono::duration<double>(now - first_trial_).count() / (trial_ - 1);
    text << ", about " << seconds_text(per_trial_s * (total_ - trial_ + 1)) << " left";
  }
  if (!detail_.empty()) text << " (" << detail_ << ")";
  return text.str();
}

void StatusLine::changed_locked() {
  if (terminal_) {
    draw_locked();
    return;
  }
  const Clock::time_point now = Clock::now();
  if (last_plain_ && now - *last_plain_ < kPlainLinePeriod) return;
  last_plain_ = now;
  out_ << "  " << escaped_for_terminal(text_locked()) << "\n" << std::flush;
}

void StatusLine::draw_locked() {
  if (terminal_) out_ << kClearLine << escaped_for_terminal(text_locked()) << std::flush;
}

void StatusLine::print_line(const std::string& line) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (terminal_) out_ << kClearLine;
  out_ << escaped_for_terminal(line, true) << "\n";
  draw_locked();
  out_ << std::flush;
}

StatusLine::LineBuffer::int_type StatusLine::LineBuffer::overflow(int_type ch) {
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  const char c = traits_type::to_char_type(ch);
  if (c == '\n') {
    owner_.print_line(pending_);
    pending_.clear();
  } else {
    pending_ += c;
  }
  return ch;
}

std::streamsize StatusLine::LineBuffer::xsputn(const char* text, std::streamsize count) {
  for (std::streamsize i = 0; i < count; ++i) overflow(traits_type::to_int_type(text[i]));
  return count;
}

}  // namespace glarelab
