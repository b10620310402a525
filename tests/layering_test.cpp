// The layers' one direction of dependency (docs/ARCHITECTURE.md "Layers"), checked on every
// `#include "..."` of the source tree, in the manner of Chromium's checkdeps:
//   core <- glare <- stimuli <- runner;  core <- protocols <- runner;  core <- analysis <- runner,
// where protocols may read glare's parameter types (and nothing else of glare). A violation is
// reported as "FILE:LINE: LAYER may not include TARGET".
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "scratch_dir.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kLayers = {"core", "glare", "stimuli", "protocols", "analysis", "runner"};

// The layers each layer may include (itself included).
const std::map<std::string, std::set<std::string>>& allowed_layers() {
  static const std::map<std::string, std::set<std::string>> allowed = {
      {"core", {"core"}},
      {"glare", {"core", "glare"}},
      {"stimuli", {"core", "glare", "stimuli"}},
      {"protocols", {"core", "glare", "protocols"}},
      {"analysis", {"core", "analysis"}},
      {"runner", {"core", "glare", "stimuli", "protocols", "analysis", "runner"}},
  };
  return allowed;
}

// What protocols may read of glare: the plain parameter types its experiment files fill in.
const std::set<std::string>& glare_parameter_headers() {
  static const std::set<std::string> headers = {"glare/eye/eye_parameters.h", "glare/glare_spec.h", "glare/analytic/hybrid_handover.h"};
  return headers;
}

// One include of the tree: the including file (relative to root), its layer, the line number and
// the included path.
struct TreeInclude {
  std::string file;
  std::string layer;
  int line = 0;
  std::string target;
};

// Every `#include "..."` of the layers' .h and .cpp files under `root`, layer by layer in kLayers'
// order, files in path order, lines in order.
std::vector<TreeInclude> tree_includes(const fs::path& root) {
  static const std::regex include_line(R"(^\s*#\s*include\s*"([^"]+)\")");
  std::vector<TreeInclude> includes;
  for (const std::string& layer : kLayers) {
    if (!fs::is_directory(root / layer)) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::recursive_directory_iterator(root / layer)) {
      const std::string extension = entry.path().extension().string();
      if (entry.is_regular_file() && (extension == ".h" || extension == ".cpp")) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      std::ifstream in(file);
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        std::smatch match;
        if (std::regex_search(line, match, include_line))
          includes.push_back({fs::relative(file, root).string(), layer, number, match[1]});
      }
    }
  }
  return includes;
}

// The layer an included path belongs to, or empty for a generated or system header.
std::string layer_of(const std::string& target) {
  if (target.find('/') == std::string::npos) return {};
  const std::string folder = target.substr(0, target.find('/'));
  return std::find(kLayers.begin(), kLayers.end(), folder) == kLayers.end() ? std::string() : folder;
}

// Every upward include under `root`, as "FILE:LINE: LAYER may not include TARGET" (FILE relative
// to root), in path order.
std::vector<std::string> layering_violations(const fs::path& root) {
  std::vector<std::string> violations;
  for (const TreeInclude& include : tree_includes(root)) {
    const std::string target_layer = layer_of(include.target);
    if (target_layer.empty()) continue;
    bool allowed = allowed_layers().at(include.layer).contains(target_layer);
    if (include.layer == "protocols" && target_layer == "glare")
      allowed = glare_parameter_headers().contains(include.target);
    if (!allowed)
      violations.push_back(include.file + ":" + std::to_string(include.line) + ": " + include.layer +
                           " may not include " + include.target);
  }
  return violations;
}

// The public faces (docs/ARCHITECTURE.md, "Public faces"): for each layer with a line there, the
// headers other layers may include. The lines run from the paragraph that starts
// "**Public faces.**" to the next paragraph that starts with "**"; a line "- `glare/`: ..." starts a
// layer's list, and every backticked name ending in ".h" after it joins that list.
std::map<std::string, std::set<std::string>> public_faces(const fs::path& document) {
  static const std::regex layer_line(R"(^- `([a-z]+)/`:)");
  static const std::regex header_name(R"(`([A-Za-z0-9_./]+\.h)`)");
  std::map<std::string, std::set<std::string>> faces;
  std::ifstream in(document);
  std::string line, layer;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("**Public faces.**", 0) == 0) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line.rfind("**", 0) == 0) break;
    std::smatch match;
    if (std::regex_search(line, match, layer_line)) layer = match[1];
    if (layer.empty()) continue;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), header_name); it != std::sregex_iterator(); ++it)
      faces[layer].insert((*it)[1]);
  }
  return faces;
}

// Every include, in a layer's file, of another layer's header that is not on that layer's public
// face, as "FILE:LINE: TARGET is not on LAYER's public face" (FILE relative to root), in path
// order. core/ has no line: it is public whole.
std::vector<std::string> public_face_violations(const fs::path& root,
                                                const std::map<std::string, std::set<std::string>>& faces) {
  std::vector<std::string> violations;
  for (const TreeInclude& include : tree_includes(root)) {
    const std::string target_layer = layer_of(include.target);
    const auto face = faces.find(target_layer);
    if (target_layer == include.layer || face == faces.end() || face->second.contains(include.target)) continue;
    violations.push_back(include.file + ":" + std::to_string(include.line) + ": " + include.target + " is not on " +
                         target_layer + "'s public face");
  }
  return violations;
}

TEST(Layering, EveryIncludeOfTheTreeRunsDownTheLayers) {
  const fs::path root = GLARELAB_SOURCE_DIR;
  for (const std::string& layer : kLayers) ASSERT_TRUE(fs::is_directory(root / layer)) << layer;
  const std::vector<std::string> violations = layering_violations(root);
  EXPECT_TRUE(violations.empty()) << "includes that run against docs/ARCHITECTURE.md:\n" << test::joined(violations);
}

TEST(Layering, APlantedUpwardIncludeIsNamedWithFileAndLine) {
  // A copy of the real tree's rules on a small tree: one allowed include of each kind and one of
  // each forbidden kind, planted at known lines.
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  test::write_file(root / "core/image.h", "#pragma once\n#include <vector>\n");
  test::write_file(root / "glare/wave/psf.cpp", "#include \"glare/wave/psf.h\"\n#include \"core/image.h\"\n#include \"runner/random.h\"\n");
  test::write_file(root / "stimuli/frame.cpp", "// frame\n#include \"glare/wave/psf.h\"\n#include \"protocols/experiment.h\"\n");
  test::write_file(root / "protocols/glare_config.h",
             "#include \"glare/glare_spec.h\"\n#include \"glare/wave/psf.h\"\n#include <toml++/toml.h>\n");
  test::write_file(root / "analysis/report.cpp", "#include \"analysis/report.h\"\n  #  include \"stimuli/image.h\"\n");
  test::write_file(root / "core/gl/owner.h", "#include \"glare/gl/fft.h\"\n");
  test::write_file(root / "runner/main.cpp", "#include \"stimuli/frame.h\"\n#include \"analysis/report.h\"\n");
  const std::vector<std::string> expected = {
      "core/gl/owner.h:1: core may not include glare/gl/fft.h",
      "glare/wave/psf.cpp:3: glare may not include runner/random.h",
      "stimuli/frame.cpp:3: stimuli may not include protocols/experiment.h",
      "protocols/glare_config.h:2: protocols may not include glare/wave/psf.h",
      "analysis/report.cpp:2: analysis may not include stimuli/image.h",
  };
  EXPECT_EQ(layering_violations(root), expected) << test::joined(layering_violations(root));
}

TEST(Layering, IncludesAcrossLayersStayOnThePublicFaces) {
  const fs::path root = GLARELAB_SOURCE_DIR;
  const auto faces = public_faces(root / "docs/ARCHITECTURE.md");
  for (const std::string layer : {"glare", "stimuli", "protocols", "analysis"})
    ASSERT_TRUE(faces.contains(layer)) << "docs/ARCHITECTURE.md, \"Public faces\", has no line for " << layer;
  for (const auto& [layer, headers] : faces)
    for (const std::string& header : headers) EXPECT_TRUE(fs::is_regular_file(root / header)) << header;
  const std::vector<std::string> violations = public_face_violations(root, faces);
  EXPECT_TRUE(violations.empty()) << "includes of headers that docs/ARCHITECTURE.md does not list as public:\n"
                                  << test::joined(violations);
}

TEST(Layering, AnIncludeBehindAPublicFaceIsNamedWithFileAndLine) {
  test::ScratchDir scratch;
  const fs::path root = scratch.path();
  test::write_file(root / "docs/ARCHITECTURE.md",
             "# A\n\n**Public faces.** Lines:\n- `glare/`: `glare/glare_spec.h`,\n  `glare/wave/psf.h`.\n"
             "- `stimuli/`: `stimuli/frame.h`.\n\n**Why.** `glare/cpu/fft.h` is not a face.\n");
  test::write_file(root / "glare/wave/psf.cpp", "#include \"glare/cpu/fft.h\"\n");
  test::write_file(root / "stimuli/frame.cpp",
             "#include \"glare/wave/psf.h\"\n#include \"glare/cpu/fft.h\"\n#include \"core/image.h\"\n");
  test::write_file(root / "runner/main.cpp",
             "#include \"stimuli/frame.h\"\n#include \"stimuli/inner.h\"\n#include \"protocols/any.h\"\n");
  const auto faces = public_faces(root / "docs/ARCHITECTURE.md");
  const std::map<std::string, std::set<std::string>> expected_faces = {
      {"glare", {"glare/glare_spec.h", "glare/wave/psf.h"}}, {"stimuli", {"stimuli/frame.h"}}};
  EXPECT_EQ(faces, expected_faces);
  const std::vector<std::string> expected = {
      "stimuli/frame.cpp:2: glare/cpu/fft.h is not on glare's public face",
      "runner/main.cpp:2: stimuli/inner.h is not on stimuli's public face",
  };
  EXPECT_EQ(public_face_violations(root, faces), expected) << test::joined(public_face_violations(root, faces));
}

}  // namespace
}  // namespace glarelab
