// Sizes a reader can hold: no source file outside tests/ over 500 lines and no function over 150
// lines. A violation is reported as "FILE: N lines (over 500)" or "FILE:LINE: NAME is N lines
// (over 150)", FILE relative to the source root, LINE the line of the function's name.
//
// What is read: the .h, .cpp and shader (.comp, .frag, .vert) files under the folders of kFolders.
//
// What a function is: a brace-matched body `{ ... }` that follows a parameter list, found in the
// text with comments, string literals (raw strings too), character literals and preprocessor lines
// blanked out (so a brace in any of them counts for nothing; lines keep their numbers). The body
// may be preceded, after the parameter list's `)`, by qualifiers (`const`, `noexcept(...)`,
// `override`, `final`, `mutable`, `&`, `&&`), a trailing return type (`-> T`) and a constructor's
// initialiser list (`: a_(x), b_{y}`); a lambda's `[...] {` without parameters counts too. Only
// outermost bodies are measured: a lambda, a local class or a control block inside a function is
// part of that function's lines, so a long function cannot pass by moving its body into a lambda.
// A member function defined in its class is measured (a class or namespace body is not a
// function). A function's length runs from the line of its name to the line of its closing brace,
// both included, blank and comment lines counted as the reader sees them. A file whose brackets
// do not balance once stripped is reported as unreadable rather than measured wrongly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scratch_dir.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxFileLines = 500;
constexpr int kMaxFunctionLines = 150;

const std::vector<std::string> kFolders = {"core",     "glare", "stimuli", "runner", "protocols",
                                           "analysis", "bench", "fuzz",    "scripts"};
const std::set<std::string> kExtensions = {".h", ".cpp", ".comp", ".frag", ".vert"};

bool is_identifier_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

// `text` with comments, string and character literals and preprocessor directives replaced by
// spaces; newlines are kept, so every character stays on its line.
std::string stripped_source(const std::string& text) {
  std::string out = text;
  const std::size_t n = text.size();
  const auto blank = [&](std::size_t from, std::size_t to) {  // [from, to)
    for (std::size_t k = from; k < to && k < n; ++k)
      if (out[k] != '\n') out[k] = ' ';
  };
  // The end of a /* comment */ starting at `i`, past its "*/" (or the end of the text).
  const auto block_comment_end = [&](std::size_t i) {
    const std::size_t close = text.find("*/", i + 2);
    return close == std::string::npos ? n : close + 2;
  };
  bool line_start = true;  // only blanks so far on this line
  std::size_t i = 0;
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      line_start = true;
      ++i;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r') {
      ++i;
      continue;
    }
    if (c == '#' && line_start) {
      // A directive runs to the end of the line, on across backslash-newlines and /* */ comments.
      std::size_t k = i;
      while (k < n && text[k] != '\n') {
        if (text.compare(k, 2, "/*") == 0) {
          k = block_comment_end(k);
        } else if (text[k] == '\\' && k + 1 < n && text[k + 1] == '\n') {
          k += 2;
        } else {
          ++k;
        }
      }
      blank(i, k);
      i = k;
      continue;
    }
    line_start = false;
    if (text.compare(i, 2, "//") == 0) {
      std::size_t k = text.find('\n', i);
      if (k == std::string::npos) k = n;
      blank(i, k);
      i = k;
      continue;
    }
    if (text.compare(i, 2, "/*") == 0) {
      const std::size_t k = block_comment_end(i);
      blank(i, k);
      i = k;
      continue;
    }
    if (c == 'R' && i + 1 < n && text[i + 1] == '"') {
      // A raw string R"delim( ... )delim", alone or after an encoding prefix (u8R, uR, UR, LR).
      std::size_t start = i;
      while (start > 0 && is_identifier_char(text[start - 1])) --start;
      const std::string_view prefix(text.data() + start, i - start);
      if (prefix.empty() || prefix == "u8" || prefix == "u" || prefix == "U" || prefix == "L") {
        const std::size_t open = text.find('(', i + 2);
        if (open != std::string::npos) {
          const std::string close = ")" + text.substr(i + 2, open - (i + 2)) + "\"";
          const std::size_t end = text.find(close, open + 1);
          const std::size_t k = end == std::string::npos ? n : end + close.size();
          blank(i + 1, k);
          i = k;
          continue;
        }
      }
    }
    if (c == '"' || c == '\'') {
      if (c == '\'' && i > 0 && is_identifier_char(text[i - 1])) {
        // After a letter or digit a quote is a digit separator (1'000) unless the word before it
        // is a character literal's encoding prefix (u8'a', u'a', U'a', L'a').
        std::size_t start = i;
        while (start > 0 && is_identifier_char(text[start - 1])) --start;
        const std::string_view word(text.data() + start, i - start);
        if (word != "u8" && word != "u" && word != "U" && word != "L") {
          ++i;
          continue;
        }
      }
      std::size_t k = i + 1;
      while (k < n && text[k] != c && text[k] != '\n') k += text[k] == '\\' ? 2 : 1;
      k = std::min(n, k + 1);
      blank(i, k);
      i = k;
      continue;
    }
    ++i;
  }
  return out;
}

struct Token {
  std::string_view text;
  int line = 0;
};

// Words (identifiers and numbers), "::", "->" and single punctuation characters.
std::vector<Token> tokens_of(const std::string& code) {
  std::vector<Token> tokens;
  int line = 1;
  const std::size_t n = code.size();
  for (std::size_t i = 0; i < n;) {
    const char c = code[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++i;
    } else if (is_identifier_char(c)) {
      std::size_t k = i;
      while (k < n && is_identifier_char(code[k])) ++k;
      tokens.push_back({std::string_view(code.data() + i, k - i), line});
      i = k;
    } else if (code.compare(i, 2, "::") == 0 || code.compare(i, 2, "->") == 0) {
      tokens.push_back({std::string_view(code.data() + i, 2), line});
      i += 2;
    } else {
      tokens.push_back({std::string_view(code.data() + i, 1), line});
      ++i;
    }
  }
  return tokens;
}

bool is_word(const Token& token) { return is_identifier_char(token.text.front()); }

// The scanner of one file: the tokens, each bracket's partner, and the outermost function bodies.
class FunctionFinder {
 public:
  // `code` is the stripped text (stripped_source); the finder keeps it, its tokens point into it.
  explicit FunctionFinder(std::string code)
      : code_(std::move(code)), tokens_(tokens_of(code_)), partner_(tokens_.size(), kNone) {
    std::vector<std::size_t> open;
    for (std::size_t i = 0; i < tokens_.size(); ++i) {
      const std::string_view t = tokens_[i].text;
      if (t == "(" || t == "[" || t == "{") {
        open.push_back(i);
      } else if (t == ")" || t == "]" || t == "}") {
        const char opener = t == ")" ? '(' : t == "]" ? '[' : '{';
        if (open.empty() || tokens_[open.back()].text.front() != opener) {
          balanced_ = false;
          return;
        }
        partner_[i] = open.back();
        partner_[open.back()] = i;
        open.pop_back();
      }
    }
    balanced_ = open.empty();
  }

  FunctionFinder(const FunctionFinder&) = delete;
  FunctionFinder& operator=(const FunctionFinder&) = delete;

  bool balanced() const { return balanced_; }

  struct Function {
    std::string name;
    int first_line = 0;  // the line of its name
    int last_line = 0;   // the line of its closing brace
  };

  // Every outermost function body, in order.
  std::vector<Function> functions() const {
    std::vector<Function> found;
    for (std::size_t i = 0; i < tokens_.size(); ++i) {
      if (tokens_[i].text != "{") continue;
      const std::size_t name = function_name(i);
      if (name == kNone) continue;  // a namespace, class, enum or initialiser: look inside it
      found.push_back({name_text(name), tokens_[name].line, tokens_[partner_[i]].line});
      i = partner_[i];  // whatever is inside belongs to this function
    }
    return found;
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  bool is(std::size_t i, std::string_view text) const { return i != kNone && tokens_[i].text == text; }
  static std::size_t before(std::size_t i) { return i == 0 ? kNone : i - 1; }

  // Steps back over what may stand between a parameter list's `)` and the body or initialiser
  // list: qualifiers, `noexcept(...)` and a trailing return type.
  std::size_t skip_qualifiers(std::size_t i) const {
    static const std::set<std::string_view> qualifiers = {"const", "volatile", "noexcept", "override", "final",
                                                          "mutable", "&",       "constexpr", "try"};
    for (;;) {
      if (i == kNone) return i;
      if (qualifiers.contains(tokens_[i].text)) {
        i = before(i);
      } else if (is(i, ")") && is(before(partner_[i]), "noexcept")) {
        i = before(before(partner_[i]));
      } else {
        // A trailing return type: words, `::`, `<`, `>`, `,`, `*`, `&` back to a `->`.
        std::size_t k = i;
        while (k != kNone && (is_word(tokens_[k]) || is(k, "::") || is(k, "<") || is(k, ">") || is(k, ",") ||
                              is(k, "*") || is(k, "&")))
          k = before(k);
        if (k == kNone || !is(k, "->") || k == i) return i;
        i = before(k);
      }
    }
  }

  // The token naming the function whose body opens at `open` (the word before its parameter
  // list, or the lambda's `[`), or kNone when that brace opens no function body.
  std::size_t function_name(std::size_t open) const {
    const std::size_t last = skip_qualifiers(before(open));
    if (last == kNone) return kNone;
    if (is(last, "]")) {
      // `[captures] {`: a lambda, unless the brackets are an array's size (`int a[3]{...}`).
      const std::size_t lead = before(partner_[last]);
      return lead != kNone && (is_word(tokens_[lead]) || is(lead, "]") || is(lead, ")")) ? kNone : partner_[last];
    }
    if (!is(last, ")") && !is(last, "}")) return kNone;
    // Back over a constructor's initialiser list, `: a_(x), b_{y}`, to its parameter list.
    std::size_t close = last;
    for (;;) {
      const std::size_t opener = partner_[close];
      // Back over the name before the brackets and the words, `::` and template arguments before
      // it (a base class, or the function's own name and return type).
      std::size_t k = before(opener);
      for (int angle_depth = 0; k != kNone; k = before(k)) {
        if (is(k, ">")) {
          ++angle_depth;
        } else if (is(k, "<")) {
          --angle_depth;
        } else if (!is_word(tokens_[k]) && !is(k, "::")) {
          const bool inside_template_arguments = angle_depth > 0 && !is(k, ";") && !is(k, "{") && !is(k, "}");
          if (!inside_template_arguments) break;
        }
      }
      const bool label =
          is(k, ":") && (is(before(k), "public") || is(before(k), "private") || is(before(k), "protected"));
      if (k != kNone && (is(k, ",") || (is(k, ":") && !label))) {
        const std::size_t previous = is(k, ":") ? skip_qualifiers(before(k)) : before(k);
        if (is(previous, ")") || (is(previous, "}") && is(k, ","))) {
          close = previous;
          continue;
        }
        return kNone;
      }
      // `close` ends the parameter list, unless it is a brace (an initialiser's `T x{...} {`).
      if (is(close, "}")) return kNone;
      const std::size_t name = before(opener);
      if (name == kNone) return kNone;
      const bool call_operator = is(name, ")") && is(before(name), "(") && is(before(before(name)), "operator");
      if (is(before(name), "operator") || call_operator) return name;  // operator=, operator bool, operator()
      if (is(name, "]")) return name;  // a lambda, or operator[]
      static const std::set<std::string_view> statements = {"if", "for", "while", "switch", "catch", "return"};
      return is_word(tokens_[name]) && !statements.contains(tokens_[name].text) ? name : kNone;
    }
  }

  // "Class::method", "operator()", "free_function" or "lambda".
  std::string name_text(std::size_t name) const {
    std::string text(tokens_[name].text);
    std::size_t k = before(name);
    const bool call_operator = is(name, ")") && is(before(name), "(") && is(before(before(name)), "operator");
    const bool index_operator = is(name, "]") && is(before(name), "[") && is(before(before(name)), "operator");
    if (call_operator || index_operator) {
      text = call_operator ? "operator()" : "operator[]";
      k = before(before(before(name)));
    } else if (is(name, "[") || is(name, "]")) {
      return "lambda";
    } else if (is(k, "operator")) {
      text = "operator" + std::string(is_word(tokens_[name]) ? " " : "") + text;
      k = before(k);
    }
    if (is(k, "~")) {
      text = "~" + text;
      k = before(k);
    }
    while (is(k, "::") && before(k) != kNone && is_word(tokens_[before(k)])) {
      text = std::string(tokens_[before(k)].text) + "::" + text;
      k = before(before(k));
    }
    return text;
  }

  std::string code_;
  std::vector<Token> tokens_;
  std::vector<std::size_t> partner_;
  bool balanced_ = true;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

int line_count(const std::string& text) {
  const auto newlines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return newlines + (!text.empty() && text.back() != '\n' ? 1 : 0);
}

// Every file and function over its limit under `root`, in path order.
std::vector<std::string> size_violations(const fs::path& root) {
  std::vector<fs::path> files;
  for (const std::string& folder : kFolders) {
    if (!fs::is_directory(root / folder)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root / folder))
      if (entry.is_regular_file() && kExtensions.contains(entry.path().extension().string()))
        files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<std::string> violations;
  for (const fs::path& file : files) {
    const std::string name = fs::relative(file, root).string();
    const std::string text = read_text(file);
    const int lines = line_count(text);
    if (lines > kMaxFileLines)
      violations.push_back(name + ": " + std::to_string(lines) + " lines (over " + std::to_string(kMaxFileLines) + ")");
    const FunctionFinder finder(stripped_source(text));
    if (!finder.balanced()) {
      violations.push_back(name + ": brackets unbalanced outside comments and strings, functions unmeasured");
      continue;
    }
    for (const FunctionFinder::Function& function : finder.functions()) {
      const int function_lines = function.last_line - function.first_line + 1;
      if (function_lines > kMaxFunctionLines)
        violations.push_back(name + ":" + std::to_string(function.first_line) + ": " + function.name + " is " +
                             std::to_string(function_lines) + " lines (over " + std::to_string(kMaxFunctionLines) +
                             ")");
    }
  }
  return violations;
}

// `count` lines of `line`.
std::string lines_of(int count, const std::string& line) {
  std::string text;
  for (int k = 0; k < count; ++k) text += line + "\n";
  return text;
}

TEST(SourceSize, NoFileOrFunctionOfTheTreeIsTooLong) {
  const fs::path root = GLARELAB_SOURCE_DIR;
  for (const std::string& folder : kFolders) ASSERT_TRUE(fs::is_directory(root / folder)) << folder;
  const std::vector<std::string> violations = size_violations(root);
  EXPECT_TRUE(violations.empty()) << "split these by concept (static helpers, or a second file):\n"
                                  << test::joined(violations);
}

TEST(SourceSize, PlantedLongFilesAndFunctionsAreNamedWithFileAndLine) {
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  // Files: one line over and one at the limit; the limit does not apply to tests/, to folders
  // outside kFolders or to other extensions.
  test::write_file(root / "core/long.h", lines_of(501, "// a line"));
  test::write_file(root / "core/at_limit.h", lines_of(500, "// a line"));
  test::write_file(root / "scripts/unterminated.cpp", lines_of(500, "// a line") + "// the 501st, with no newline");
  test::write_file(root / "tests/long_test.cpp", lines_of(900, "// a line"));
  test::write_file(root / "examples/long.cpp", lines_of(900, "// a line"));
  test::write_file(root / "glare/notes.txt", lines_of(900, "a line"));

  // Functions. Line 1 is the name's line, the body's lines follow, then the closing brace.
  test::write_file(root / "glare/free.cpp",
             "#include <vector>\n"                                                       // 1
             "namespace glarelab {\n"                                                    // 2
             "int at_limit(int x) {\n" + lines_of(148, "  x += 1;") + "  return x; }\n"  // 3..152: 150 lines
             "static int over(int x)\n"                                                  // 153
             "{\n" + lines_of(147, "  x += 1;") + "  return x;\n}\n"                   // 154..303: 151 lines
             "}  // namespace glarelab\n");
  // A member function in its class, a constructor whose initialiser list ends in a brace, and a
  // const noexcept member with a trailing return type; the class itself is longer than 150 lines.
  test::write_file(root / "stimuli/members.h",
             "#pragma once\n"                                                          // 1
             "struct Frame {\n"                                                        // 2
             "  Frame(int w, int h)\n"                                                 // 3
             "      : w_(w), h_{h} {\n" + lines_of(148, "    w_ += h_;") + "  }\n"    // 4..153: 151 lines
             "  auto area() const noexcept -> long {\n" + lines_of(150, "    ;") + "    return w_; }\n"  // 154..305
             "  int w_;\n  int h_;\n};\n");
  // A lambda's lines count in the function that holds it, and a table of braces is no function.
  test::write_file(root / "runner/lambda.cpp",
             "const int kTable[] = {\n" + lines_of(200, "  1,") + "};\n"              // 1..202
             "void run() {\n"                                                          // 203
             "  const auto step = [&](int k) {\n" + lines_of(150, "    (void)k;") + "  };\n"  // 204..355
             "  step(1);\n}\n");                                                        // 356..357
  // Braces in comments, strings, raw strings and character literals, a digit separator and a
  // preprocessor line: read literally, they would end the function early or leave it unbalanced.
  test::write_file(root / "protocols/literals.cpp",
             "int parse() {\n"                                                         // 1
             "  // } a brace in a comment\n"                                           // 2
             "  /* } and in a block\n  comment } */\n"                                 // 3-4
             "  const char* s = \"}\\\"}\";\n"                                         // 5
             "  const char* r = R\"x(}\" )\" })x\";\n"                                 // 6
             "  const char c = '}';\n  const char q = '\\'';\n"                        // 7-8
             "  const int million = 1'000'000;\n"                                      // 9
             "#define CLOSE }\n" + lines_of(150, "  ;") + "  return million + c + q + *s + *r;\n}\n");  // 10..162
  // A shader's main.
  test::write_file(root / "glare/shaders/long.comp",
             "#version 450\nlayout(local_size_x = 8) in;\nvoid main() {\n" + lines_of(150, "  ;") + "}\n");  // 3..154
  // Control blocks and a local lambda without parameters stay inside their function, which is short.
  test::write_file(root / "analysis/short.cpp",
             "int f(int x) {\n  if (x > 0) {\n    x = 1;\n  }\n  auto g = [] { return 2; };\n  return x + g();\n}\n");
  // Unbalanced once stripped: named, not silently mis-measured.
  test::write_file(root / "bench/broken.cpp", "void f() {\n  if (true) {\n}\n");

  const std::vector<std::string> expected_violations = {
      "bench/broken.cpp: brackets unbalanced outside comments and strings, functions unmeasured",
      "core/long.h: 501 lines (over 500)",
      "glare/free.cpp:153: over is 151 lines (over 150)",
      "glare/shaders/long.comp:3: main is 152 lines (over 150)",
      "protocols/literals.cpp:1: parse is 162 lines (over 150)",
      "runner/lambda.cpp:203: run is 155 lines (over 150)",
      "scripts/unterminated.cpp: 501 lines (over 500)",
      "stimuli/members.h:3: Frame is 151 lines (over 150)",
      "stimuli/members.h:154: area is 152 lines (over 150)",
  };
  EXPECT_EQ(size_violations(root), expected_violations) << test::joined(size_violations(root));
}

}  // namespace
}  // namespace glarelab
