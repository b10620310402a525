// The texts a shader's source is handed to glShaderSource in (core/gl/shader_program.h): each
// lies within the embedded source (or is the defines' own text), each has its length, and together
// they are the source with the defines after its #version line. Without defines the source goes
// whole: the split once put the second text one past the source's terminator with a length of -1,
// so the driver read on with strlen into whatever followed the source in memory (AddressSanitizer:
// global-buffer-overflow under every program built without defines) and took the terminator itself
// into the first text.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "core/gl/shader_program.h"

namespace glarelab::gl {
namespace {

// Whether `part` lies within `whole` (an empty part at its end included).
bool within(std::string_view part, std::string_view whole) {
  return part.data() >= whole.data() && part.data() + part.size() <= whole.data() + whole.size();
}

std::string joined(const ShaderSourceTexts& texts) {
  return std::string(texts.before_defines) + texts.defines_block + std::string(texts.after_defines);
}

TEST(ShaderSourceTexts, WithoutDefinesTheSourceGoesWholeAndNothingPastIt) {
  // A source followed in memory by other text, as one embedded shader is by the next.
  const std::string memory = "#version 450 core\nvoid main() {}\n#version 450 core\nother shader";
  const std::string_view source(memory.data(), memory.find("#version", 1));
  const ShaderSourceTexts texts = shader_source_texts(source, {});
  EXPECT_EQ(texts.before_defines.data(), source.data());
  EXPECT_EQ(texts.before_defines.size(), source.size());  // not the terminator too
  EXPECT_TRUE(texts.defines_block.empty());
  EXPECT_TRUE(texts.after_defines.empty());
  EXPECT_TRUE(within(texts.after_defines, source));
  EXPECT_EQ(joined(texts), "#version 450 core\nvoid main() {}\n");
}

TEST(ShaderSourceTexts, DefinesFollowTheVersionLineAndALineDirectiveTakesTheSourceBackToItsSecondLine) {
  const std::string_view source = "#version 450 core\nlayout(local_size_x = 16) in;\nvoid main() {}\n";
  const ShaderSourceTexts texts = shader_source_texts(source, "#define TAPS 7\n#define DITHER 1");
  EXPECT_TRUE(within(texts.before_defines, source));
  EXPECT_TRUE(within(texts.after_defines, source));
  EXPECT_EQ(texts.before_defines, "#version 450 core\n");
  EXPECT_EQ(texts.defines_block, "#define TAPS 7\n#define DITHER 1\n#line 2\n");
  EXPECT_EQ(joined(texts),
            "#version 450 core\n#define TAPS 7\n#define DITHER 1\n#line 2\nlayout(local_size_x = 16) in;\nvoid main() {}\n");
}

TEST(ShaderSourceTexts, ASourceOfOneLineWithoutALineEndHasTheDefinesOnALineOfTheirOwn) {
  const std::string_view source = "#version 450 core";
  const ShaderSourceTexts texts = shader_source_texts(source, "#define A 1");
  EXPECT_EQ(texts.before_defines, source);
  EXPECT_TRUE(texts.after_defines.empty());
  EXPECT_TRUE(within(texts.after_defines, source));
  EXPECT_EQ(joined(texts), "#version 450 core\n#define A 1\n#line 2\n");
}

}  // namespace
}  // namespace glarelab::gl
