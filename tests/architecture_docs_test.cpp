// docs/ARCHITECTURE.md kept true to the tree (its section "Keeping this document true"), and the
// repository paths that comments cite kept pointing at files that exist. Three rules, each
// violation reported as "FILE:LINE: message":
//
// 1. Every source module of the layers is listed under its folder's heading. A module is a .h/.cpp
//    stem (`glare/wave/spectral_psf` for spectral_psf.h and spectral_psf.cpp) or a shader file (.comp, .frag, .vert) anywhere under
//    core/, glare/, stimuli/, runner/, protocols/ or analysis/. Only these six folders have a
//    heading ("### `glare/`"); a subfolder (glare/gl/, runner/session/) is listed under its layer's
//    heading. The module is listed when the heading's section (up to the next heading of level 3
//    or above) names one of its files in backticks, by its path from the root, by its path below
//    the layer's folder (`session/trial_run.cpp`, `gl/fft.*`) or by a tail of that path after a
//    '/' (`fft.*`, written inside the bullet that introduces the subfolder), ".*" standing for
//    any extension.
//    Reported at the heading's line.
// 2. Every file or folder the document names in backticks exists. A backticked text names one when
//    it is made only of letters, digits and "_-./" (with "*" only as the extension ".*") and ends in
//    one of kNamedExtensions, ".*" or "/". It exists when it is a path from the repository's root,
//    or a tail of a path under the section's layer folder (in a layer's section) or of any path
//    in the repository (elsewhere). Reported at the document's line.
// 3. Every repository path a comment cites exists. Comments are the rest of a line after "//" in
//    C++ and GLSL files (.h, .cpp, .c, .comp, .frag, .vert), and after a "#" that starts a line or
//    follows a blank in shell, CMake, Python and TOML files (.sh, .cmake, .py, .toml,
//    CMakeLists.txt), either outside the line's string literals; /* */ comments are not read. The
//    prose of docs/ARCHITECTURE.md (outside backticks) is read too. A cited path is a run of
//    letters, digits and "_-./" that starts with one of the repository's top-level folders
//    (`docs/`, `glare/`, `tests/` ...) and ends in one of kNamedExtensions or ".*", or a bare
//    Markdown file name in capitals (`README.md`, `STEREO.md`: at the root or in docs/); a
//    leading "../" is dropped and trailing full stops are punctuation. Texts with "*" elsewhere
//    (`tests/glare_*_test.cpp`) are patterns, not paths, and are not checked.
//
// "The tree" is every file under the repository's root except hidden files and folders and build
// folders (a top-level folder holding CMakeCache.txt): the scan reads the source files once.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scratch_dir.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

const std::array<std::string_view, 6> kLayers = {"core", "glare", "stimuli", "runner", "protocols", "analysis"};
// The extensions a name in the document or a cited path may end in.
const std::array<std::string_view, 16> kNamedExtensions = {"h",  "cpp", "c",    "comp", "frag", "vert", "md",  "toml",
                                                           "csv", "sh", "txt",  "cmake", "py",  "json", "exr", "png"};
const std::string kDocument = "docs/ARCHITECTURE.md";

bool is_layer(std::string_view folder) {
  return std::find(kLayers.begin(), kLayers.end(), folder) != kLayers.end();
}

// The extension after the last '.' of the last path component ("" when there is none).
std::string_view extension_of(std::string_view path) {
  const std::size_t slash = path.rfind('/');
  const std::size_t dot = path.rfind('.');
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
  return path.substr(dot + 1);
}

std::string_view stem_of(std::string_view path) {
  const std::string_view extension = extension_of(path);
  return extension.empty() ? path : path.substr(0, path.size() - extension.size() - 1);
}

// The repository as relative paths with '/' separators.
struct Tree {
  fs::path root;
  std::vector<std::string> files;  // sorted
  std::set<std::string> folders;
  std::set<std::string> top_folders;

  bool has_file(const std::string& path) const { return std::binary_search(files.begin(), files.end(), path); }
};

Tree read_tree(const fs::path& root) {
  Tree tree;
  tree.root = root;
  for (const auto& top : fs::directory_iterator(root)) {
    const std::string name = top.path().filename().string();
    if (name.starts_with('.')) continue;
    if (top.is_regular_file()) {
      tree.files.push_back(name);
      continue;
    }
    if (!top.is_directory() || fs::exists(top.path() / "CMakeCache.txt")) continue;
    tree.top_folders.insert(name);
    tree.folders.insert(name);
    for (auto it = fs::recursive_directory_iterator(top.path()); it != fs::recursive_directory_iterator(); ++it) {
      if (it->path().filename().string().starts_with('.')) {
        if (it->is_directory()) it.disable_recursion_pending();
        continue;
      }
      const std::string relative = it->path().lexically_relative(root).generic_string();
      if (it->is_directory()) tree.folders.insert(relative);
      else if (it->is_regular_file()) tree.files.push_back(relative);
    }
  }
  std::sort(tree.files.begin(), tree.files.end());
  return tree;
}

std::vector<std::string> read_lines(const fs::path& path) {
  std::vector<std::string> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Whether `path` is `name`, or ends in "/" + name; with name "stem.*", whether its stem does and
// it has an extension.
bool names_path(std::string_view path, std::string_view name) {
  if (name.ends_with(".*")) {
    if (extension_of(path).empty()) return false;
    path = stem_of(path);
    name.remove_suffix(2);
  }
  if (path == name) return true;
  return path.size() > name.size() && path.ends_with(name) && path[path.size() - name.size() - 1] == '/';
}

bool ends_in_named_extension(std::string_view name) {
  if (name.ends_with(".*")) return name.size() > 2 && name[name.size() - 3] != '/';
  const std::string_view extension = extension_of(name);
  return std::find(kNamedExtensions.begin(), kNamedExtensions.end(), extension) != kNamedExtensions.end() &&
         extension.size() + 1 < name.size() && name[name.size() - extension.size() - 2] != '/';
}

bool is_path_character(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.' || c == '/';
}

// Rule 2's "names a file or folder": letters, digits, "_-./", '*' only in a final ".*", and a
// named extension or a final '/'.
bool is_file_name(std::string_view text) {
  if (text.empty()) return false;
  const std::string_view body = text.ends_with(".*") ? text.substr(0, text.size() - 1) : text;
  if (!std::all_of(body.begin(), body.end(), is_path_character)) return false;
  if (text.ends_with('/')) return text.size() > 1;
  return ends_in_named_extension(text);
}

// Files (and, for a name ending in '/', folders with a '/' appended) that `name` names: the path
// from the root, or a tail of a path under `under` ("" for anywhere).
std::vector<std::string> named_by(const Tree& tree, const std::string& name, const std::string& under) {
  const std::string scope = under.empty() ? "" : under + "/";
  std::vector<std::string> named;
  if (name.ends_with('/')) {
    const std::string bare = name.substr(0, name.size() - 1);
    for (const std::string& path : tree.folders)
      if (path == bare || (path.starts_with(scope) && names_path(path, bare))) named.push_back(path + "/");
    return named;
  }
  for (const std::string& path : tree.files) {
    const bool from_root =
        name.ends_with(".*") ? !extension_of(path).empty() && stem_of(path) == stem_of(name) : path == name;
    if (from_root || (path.starts_with(scope) && names_path(path, name))) named.push_back(path);
  }
  return named;
}

// A line of the document with its backticked texts and its prose (the rest).
struct DocumentLine {
  int number = 0;
  std::optional<std::string> layer;  // the layer whose section the line is in
  std::vector<std::string> backticked;
  std::string prose;
};

struct Document {
  std::vector<DocumentLine> lines;
  std::map<std::string, int> heading_line;  // layer -> line of "### `layer/`"
};

Document read_document(const Tree& tree) {
  Document document;
  std::optional<std::string> layer;
  bool in_fence = false;
  int number = 0;
  for (const std::string& text : read_lines(tree.root / kDocument)) {
    ++number;
    if (text.starts_with("```")) {
      in_fence = !in_fence;
      continue;
    }
    if (in_fence) continue;
    if (text.starts_with("#")) {
      const std::size_t level = text.find_first_not_of('#');
      if (level <= 3) layer.reset();
      if (level == 3 && text.starts_with("### `") && text.ends_with("/`")) {
        const std::string folder = text.substr(5, text.size() - 7);
        if (is_layer(folder)) {
          layer = folder;
          document.heading_line[folder] = number;
        }
      }
      continue;
    }
    DocumentLine line{number, layer, {}, {}};
    std::size_t at = 0;
    while (at < text.size()) {
      const std::size_t open = text.find('`', at);
      const std::size_t close = open == std::string::npos ? std::string::npos : text.find('`', open + 1);
      if (close == std::string::npos) {
        line.prose += text.substr(at);
        break;
      }
      line.prose += text.substr(at, open - at) + " ";
      line.backticked.push_back(text.substr(open + 1, close - open - 1));
      at = close + 1;
    }
    document.lines.push_back(std::move(line));
  }
  return document;
}

// Rule 1.
std::vector<std::string> unlisted_modules(const Tree& tree) {
  const Document document = read_document(tree);
  std::map<std::string, std::set<std::string>> listed;  // layer -> files its section names
  for (const DocumentLine& line : document.lines) {
    if (!line.layer) continue;
    for (const std::string& text : line.backticked) {
      if (!is_file_name(text) || text.ends_with('/')) continue;
      for (const std::string& file : named_by(tree, text, *line.layer))
        if (file.starts_with(*line.layer + "/")) listed[*line.layer].insert(file);
    }
  }
  // module -> its files, per layer, in path order
  std::map<std::string, std::vector<std::string>> modules;
  for (const std::string& file : tree.files) {
    const std::string layer = file.substr(0, file.find('/'));
    if (!is_layer(layer) || file.find('/') == std::string::npos) continue;
    const std::string_view extension = extension_of(file);
    if (extension == "h" || extension == "cpp") modules[std::string(stem_of(file))].push_back(file);
    else if (extension == "comp" || extension == "frag" || extension == "vert") modules[file].push_back(file);
  }
  std::vector<std::string> violations;
  for (const std::string_view layer_view : kLayers) {
    const std::string layer(layer_view);
    if (!fs::is_directory(tree.root / layer)) continue;
    const auto heading = document.heading_line.find(layer);
    if (heading == document.heading_line.end()) {
      violations.push_back(kDocument + ":1: no heading ### `" + layer + "/`");
      continue;
    }
    for (const auto& [module, files] : modules) {
      if (!module.starts_with(layer + "/")) continue;
      const bool is_listed = std::any_of(files.begin(), files.end(),
                                         [&](const std::string& file) { return listed[layer].contains(file); });
      if (!is_listed)
        violations.push_back(kDocument + ":" + std::to_string(heading->second) + ": ### `" + layer +
                             "/` does not list " + module + " (" + files.front() + ")");
    }
  }
  return violations;
}

// Rule 2.
std::vector<std::string> missing_named_files(const Tree& tree) {
  const Document document = read_document(tree);
  std::vector<std::string> violations;
  for (const DocumentLine& line : document.lines) {
    for (const std::string& text : line.backticked) {
      if (!is_file_name(text)) continue;
      if (named_by(tree, text, line.layer.value_or("")).empty())
        violations.push_back(kDocument + ":" + std::to_string(line.number) + ": names `" + text +
                             "`, which is not in the repository");
    }
  }
  return violations;
}

bool is_capital_markdown_name(std::string_view name) {
  if (!name.ends_with(".md") || name.size() < 4 || !std::isupper(static_cast<unsigned char>(name.front())))
    return false;
  return std::all_of(name.begin(), name.end() - 3, [](char c) {
    return std::isupper(static_cast<unsigned char>(c)) != 0 || std::isdigit(static_cast<unsigned char>(c)) != 0 ||
           c == '_';
  });
}

// The repository paths `text` cites (rule 3) that are not in the tree.
std::vector<std::string> missing_citations(const Tree& tree, std::string_view text) {
  std::vector<std::string> missing;
  const auto is_run_character = [](char c) { return is_path_character(c) || c == '*'; };
  std::size_t at = 0;
  while (at < text.size()) {
    if (!is_run_character(text[at])) {
      ++at;
      continue;
    }
    std::size_t end = at;
    while (end < text.size() && is_run_character(text[end])) ++end;
    std::string_view run = text.substr(at, end - at);
    at = end;
    while (run.ends_with('.')) run.remove_suffix(1);
    while (run.starts_with("../")) run.remove_prefix(3);
    const std::string_view body = run.ends_with(".*") ? run.substr(0, run.size() - 1) : run;
    if (body.find('*') != std::string_view::npos || !ends_in_named_extension(run)) continue;
    const std::size_t slash = run.find('/');
    if (slash == std::string_view::npos) {
      if (!is_capital_markdown_name(run)) continue;
      const std::string name(run);
      if (!tree.has_file(name) && !tree.has_file("docs/" + name)) missing.push_back(name);
      continue;
    }
    if (!tree.top_folders.contains(std::string(run.substr(0, slash)))) continue;
    const std::string path(run);
    const bool exists =
        run.ends_with(".*") ? std::any_of(tree.files.begin(), tree.files.end(),
                                          [&](const std::string& file) {
                                            return !extension_of(file).empty() && stem_of(file) == stem_of(path);
                                          })
                            : tree.has_file(path);
    if (!exists) missing.push_back(path);
  }
  return missing;
}

// Where a comment starts on `line`: the first "//" (or, with `hash`, the first '#' at the line's
// start or after a blank) outside a string or character literal; npos when there is none.
std::size_t comment_start(std::string_view line, bool hash) {
  bool in_string = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (!hash && c == '\'') {  // a character literal, 'x' or '\x'
      const std::size_t close = line.find('\'', i + 1);
      if (close != std::string_view::npos && close <= i + 3) i = close;
    } else if (hash ? c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')
                    : c == '/' && i + 1 < line.size() && line[i + 1] == '/') {
      return i;
    }
  }
  return std::string_view::npos;
}

enum class CommentStyle { none, slashes, hash };

// How the comments of `file` start (rule 3's source files), from its name.
CommentStyle comment_style(const std::string& file) {
  static const std::set<std::string_view> slash_comments = {"h", "cpp", "c", "comp", "frag", "vert"};
  static const std::set<std::string_view> hash_comments = {"sh", "cmake", "py", "toml"};
  const std::string_view extension = extension_of(file);
  if (slash_comments.contains(extension)) return CommentStyle::slashes;
  if (hash_comments.contains(extension) || file == "CMakeLists.txt" || file.ends_with("/CMakeLists.txt"))
    return CommentStyle::hash;
  return CommentStyle::none;
}

// The comment on a line, or "".
std::string_view comment_of(CommentStyle style, std::string_view line) {
  if (style == CommentStyle::none) return {};
  const bool hash = style == CommentStyle::hash;
  const std::size_t start = comment_start(line, hash);
  return start == std::string_view::npos ? std::string_view{} : line.substr(start + (hash ? 1 : 2));
}

// Rule 3.
std::vector<std::string> missing_cited_paths(const Tree& tree) {
  std::vector<std::string> violations;
  for (const std::string& file : tree.files) {
    if (file == kDocument) {
      for (const DocumentLine& line : read_document(tree).lines)
        for (const std::string& path : missing_citations(tree, line.prose))
          violations.push_back(file + ":" + std::to_string(line.number) + ": cites " + path +
                               ", which is not in the repository");
      continue;
    }
    const CommentStyle style = comment_style(file);
    if (style == CommentStyle::none) continue;
    const std::vector<std::string> lines = read_lines(tree.root / file);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string_view comment = comment_of(style, lines[i]);
      if (comment.empty()) continue;
      for (const std::string& path : missing_citations(tree, comment))
        violations.push_back(file + ":" + std::to_string(i + 1) + ": cites " + path +
                             ", which is not in the repository");
    }
  }
  return violations;
}

const Tree& repository() {
  static const Tree tree = read_tree(GLARELAB_SOURCE_DIR);
  return tree;
}

TEST(ArchitectureDocs, EveryModuleIsListedUnderItsFolderHeading) {
  for (const std::string_view layer : kLayers) ASSERT_TRUE(repository().top_folders.contains(std::string(layer))) << layer;
  const std::vector<std::string> violations = unlisted_modules(repository());
  EXPECT_TRUE(violations.empty()) << "modules missing from docs/ARCHITECTURE.md:\n" << test::joined(violations);
}

TEST(ArchitectureDocs, EveryFileTheDocumentNamesExists) {
  const std::vector<std::string> violations = missing_named_files(repository());
  EXPECT_TRUE(violations.empty()) << test::joined(violations);
}

TEST(ArchitectureDocs, EveryRepositoryPathACommentCitesExists) {
  const std::vector<std::string> violations = missing_cited_paths(repository());
  EXPECT_TRUE(violations.empty()) << test::joined(violations);
}

// A small tree: two layers' headings, modules in folders and subfolders, shaders.
void write_small_tree(const fs::path& root) {
  for (const std::string_view layer : kLayers) fs::create_directories(root / layer);
  test::write_file(root / "glare/psf.h", "#pragma once\n");
  test::write_file(root / "glare/psf.cpp", "#include \"glare/psf.h\"\n");
  test::write_file(root / "glare/gl/gl_fft.h", "#pragma once\n");
  test::write_file(root / "glare/shaders/sum_reduce.comp", "#version 450\n");
  test::write_file(root / "runner/session/trial_run.cpp", "\n");
  test::write_file(root / "runner/session/trial_record.h", "#pragma once\n");
  test::write_file(root / "runner/main.cpp", "\n");
  test::write_file(root / "stimuli/layout.h", "#pragma once\n");
  test::write_file(root / "tests/layering_test.cpp", "\n");
  test::write_file(root / "docs/STEREO.md", "# Stereo\n");
}

TEST(ArchitectureDocs, AnUnlistedModuleIsNamedWithItsHeadingsLine) {
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  write_small_tree(root);
  test::write_file(root / "analysis/report.cpp", "\n");
  test::write_file(root / "core/image.h", "#pragma once\n");
  test::write_file(root / "stimuli/shaders/fullscreen.vert", "#version 450\n");
  test::write_file(root / kDocument,
             "# Architecture\n"                                                   // 1
             "### `core/`\n"                                                      // 2
             "- `image.*`: images.\n"                                             // 3
             "### `runner/`\n"                                                    // 4
             "- `main.cpp`, `session/trial_run.cpp`; `stimuli/layout.h` is not runner's.\n"  // 5
             "### `stimuli/`\n"                                                   // 6
             "- `shaders/`: the renderer's shaders. `psf.*` is glare's.\n"        // 7
             "### `protocols/`\n"                                                 // 8
             "### `analysis/`\n"                                                  // 9
             "### `glare/`\n"                                                     // 10
             "- `psf.h`, `gl/` (`gl_fft.*`), `shaders/sum_reduce.comp`\n"         // 11
             "## Elsewhere\n"                                                     // 12
             "- `report.*` is not under analysis' heading.\n");                   // 13
  // In the layers' order (core, glare, stimuli, runner, protocols, analysis), then by path.
  const std::vector<std::string> expected = {
      "docs/ARCHITECTURE.md:6: ### `stimuli/` does not list stimuli/layout (stimuli/layout.h)",
      "docs/ARCHITECTURE.md:6: ### `stimuli/` does not list stimuli/shaders/fullscreen.vert "
      "(stimuli/shaders/fullscreen.vert)",
      "docs/ARCHITECTURE.md:4: ### `runner/` does not list runner/session/trial_record (runner/session/trial_record.h)",
      "docs/ARCHITECTURE.md:9: ### `analysis/` does not list analysis/report (analysis/report.cpp)",
  };
  EXPECT_EQ(unlisted_modules(read_tree(root)), expected) << test::joined(unlisted_modules(read_tree(root)));

  // A missing heading is named too.
  test::write_file(root / kDocument, "### `core/`\n- `image.h`\n");
  const std::vector<std::string> violations = unlisted_modules(read_tree(root));
  ASSERT_FALSE(violations.empty());
  EXPECT_EQ(violations.front(), "docs/ARCHITECTURE.md:1: no heading ### `glare/`");
}

TEST(ArchitectureDocs, ANamedFileThatDoesNotExistIsNamedWithItsLine) {
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  write_small_tree(root);
  test::write_file(root / kDocument,
             "# Architecture\n"                                                                  // 1
             "`glare/psf.h` and `docs/STEREO.md` exist; `frames.dropped` and `[glare] a.h` are no file names.\n"  // 2
             "```\n"                                                                             // 3
             "`glare/in_a_fence.h`\n"                                                            // 4
             "```\n"                                                                             // 5
             "### `glare/`\n"                                                                    // 6
             "- `psf.*`, `gl/gl_fft.h`, `gl_fft.h`, `psf_gone.*`, `shaders/`, `kernels/`\n"      // 7
             "- `trial_run.cpp` is runner's, `runner/session/trial_run.cpp` is from the root\n"   // 8
             "### `runner/`\n"                                                                   // 9
             "- `session/trial_record.h`, `trial_run.cpp`, `cli/`\n"                             // 10
             "## Elsewhere\n"                                                                    // 11
             "- `tests/`: `layering_test.cpp`, `test_support.h`.\n");                           // 12
  const std::vector<std::string> expected = {
      "docs/ARCHITECTURE.md:7: names `psf_gone.*`, which is not in the repository",
      "docs/ARCHITECTURE.md:7: names `kernels/`, which is not in the repository",
      "docs/ARCHITECTURE.md:8: names `trial_run.cpp`, which is not in the repository",
      "docs/ARCHITECTURE.md:10: names `cli/`, which is not in the repository",
      "docs/ARCHITECTURE.md:12: names `test_support.h`, which is not in the repository",
  };
  EXPECT_EQ(missing_named_files(read_tree(root)), expected) << test::joined(missing_named_files(read_tree(root)));
}

TEST(ArchitectureDocs, ACitedPathThatDoesNotExistIsNamedWithFileAndLine) {
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  write_small_tree(root);
  test::write_file(root / "README.md", "# glarelab\n");
  test::write_file(root / "glare/psf.h",
             "#pragma once\n"
             "// The image contract (DESIGN.md), see glare/psf.cpp and docs/STEREO.md.\n"
             "int f();  // tests/psf_test.cpp checks it; tests/glare_*_test.cpp are patterns.\n"
             "const char* url = \"see glare/not_a_comment.h // nor glare/in_a_string.h\";  // '\"' glare/psf.h\n");
  test::write_file(root / "runner/store/result_store.h", "// Contract (docs/DATABASE.md, ../DESIGN.md, README.md).\n");
  test::write_file(root / "tests/layering_test.cpp", "// Reads glare/psf.*, stimuli/layout.h and glare/gone.*.\n");
  test::write_file(root / "stimuli/shaders/blur.comp", "#version 450\n// the weights of glare/gl/gl_blur.h.\n");
  test::write_file(root / "scripts/setup.sh", "#!/bin/sh\necho $# # runs scripts/build.sh, then docs/STEREO.md.\n");
  test::write_file(root / "CMakeLists.txt", "# Layers (docs/LAYERS.md).\nset(x a#glare/hash.h)\n");
  test::write_file(root / "examples/demo.toml", "# The eye of glare/eye_model.h.\nname = \"glare/x.h\"\n");
  test::write_file(root / "examples/notes.txt", "// glare/not_a_source_file.h\n");
  test::write_file(root / kDocument, "# Architecture\nAs runner/cli/gone.cpp says, `glare/psf.h` is here.\n");
  const std::vector<std::string> expected = {
      "CMakeLists.txt:1: cites docs/LAYERS.md, which is not in the repository",
      "docs/ARCHITECTURE.md:2: cites runner/cli/gone.cpp, which is not in the repository",
      "examples/demo.toml:1: cites glare/eye_model.h, which is not in the repository",
      "glare/psf.h:2: cites DESIGN.md, which is not in the repository",
      "glare/psf.h:3: cites tests/psf_test.cpp, which is not in the repository",
      "runner/store/result_store.h:1: cites docs/DATABASE.md, which is not in the repository",
      "runner/store/result_store.h:1: cites DESIGN.md, which is not in the repository",
      "scripts/setup.sh:2: cites scripts/build.sh, which is not in the repository",
      "stimuli/shaders/blur.comp:2: cites glare/gl/gl_blur.h, which is not in the repository",
      "tests/layering_test.cpp:1: cites glare/gone.*, which is not in the repository",
  };
  EXPECT_EQ(missing_cited_paths(read_tree(root)), expected) << test::joined(missing_cited_paths(read_tree(root)));
}

}  // namespace
}  // namespace glarelab
