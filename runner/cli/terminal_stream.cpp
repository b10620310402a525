#include "runner/cli/terminal_stream.h"

#include <cstring>
#include <iostream>
#include <streambuf>
#include <string>

#include "core/text_limits.h"

namespace glarelab::cli {
namespace {

// Bytes at the end of `text` that start a UTF-8 sequence not yet complete: kept for the next
// write, so a character split across two writes is not escaped as two bad bytes.
std::size_t incomplete_tail(const std::string& text) {
  for (std::size_t back = 1; back <= 3 && back <= text.size(); ++back) {
    const auto byte = static_cast<unsigned char>(text[text.size() - back]);
    if ((byte & 0xC0) == 0x80) continue;  // a continuation byte: look further back
    const std::size_t length = byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : byte >= 0xC0 ? 2 : 1;
    return length > back ? back : 0;
  }
  return 0;
}

// Collects text and hands it on escaped at each line break, flush and buffer's worth.
class EscapingBuffer : public std::streambuf {
 public:
  explicit EscapingBuffer(std::streambuf* target) : target_(target) {}
  ~EscapingBuffer() override { pass_on(true); }
  EscapingBuffer(const EscapingBuffer&) = delete;
  EscapingBuffer& operator=(const EscapingBuffer&) = delete;

 protected:
  int_type overflow(int_type ch) override {
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    pending_ += traits_type::to_char_type(ch);
    if (ch == '\n' || pending_.size() >= kChunkBytes) pass_on(false);
    return ch;
  }
  std::streamsize xsputn(const char* text, std::streamsize count) override {
    pending_.append(text, static_cast<std::size_t>(count));
    if (std::memchr(text, '\n', static_cast<std::size_t>(count)) != nullptr || pending_.size() >= kChunkBytes)
      pass_on(false);
    return count;
  }
  int sync() override {
    pass_on(false);
    return target_->pubsync();
  }

 private:
  static constexpr std::size_t kChunkBytes = 4096;

  void pass_on(bool everything) {
    const std::size_t keep = everything ? 0 : incomplete_tail(pending_);
    const std::string text = escaped_for_terminal(std::string_view(pending_).substr(0, pending_.size() - keep), true);
    target_->sputn(text.data(), static_cast<std::streamsize>(text.size()));
    pending_.erase(0, pending_.size() - keep);
  }

  std::streambuf* target_;
  std::string pending_;
};

}  // namespace

struct TerminalTextGuard::Installed {
  std::streambuf* cout_target = std::cout.rdbuf();
  std::streambuf* cerr_target = std::cerr.rdbuf();
  EscapingBuffer cout_filter{cout_target};
  EscapingBuffer cerr_filter{cerr_target};
  std::ostream unescaped_cout{cout_target};
};

namespace {
std::ostream* unescaped = nullptr;  // the installed guard's, while one is installed
}  // namespace

std::ostream& unescaped_stdout() { return unescaped != nullptr ? *unescaped : std::cout; }

TerminalTextGuard::TerminalTextGuard() : installed_(std::make_unique<Installed>()) {
  std::cout.rdbuf(&installed_->cout_filter);
  std::cerr.rdbuf(&installed_->cerr_filter);
  unescaped = &installed_->unescaped_cout;
}

TerminalTextGuard::~TerminalTextGuard() {
  unescaped = nullptr;
  std::cout.flush();
  std::cerr.flush();
  std::cout.rdbuf(installed_->cout_target);
  std::cerr.rdbuf(installed_->cerr_target);
}

}  // namespace glarelab::cli
