// The cross-session cache of CIE display kernels (glare/analytic/kernel_cache.h): a second session
// gets the first one's kernel and frames bit for bit; a damaged, mismatched or linked entry is
// detected, warned about and integrated again. The reference is analytic_display_kernel itself.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "glare/analytic/kernel_cache.h"
#include "scratch_dir.h"
#include "stimuli/glare_stage.h"

namespace glarelab {
namespace {

bool same_values(const DisplayKernel& a, const DisplayKernel& b) {
  return a.half_width_px == b.half_width_px && a.half_height_px == b.half_height_px && a.channels == b.channels &&
         a.values.size() == b.values.size() &&
         std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)) == 0;
}

class KernelCache : public ::testing::Test {
 protected:
  void SetUp() override {
    before_ = kernel_cache_place();
    use_kernel_cache_folder((scratch_.path() / "kernels").string());
  }
  void TearDown() override { use_kernel_cache_folder(before_.kept() ? before_.folder : "none"); }

  test::ScratchDir scratch_;
  KernelCachePlace before_;
  const AnalyticPsf psf_ = AnalyticPsf::cie(ObserverEye{50.0, 0.3});
  const DisplayGeometry geometry_{600.0, 0.25};
};

TEST_F(KernelCache, StoredThenReadBitForBit) {
  const DisplayKernel direct = analytic_display_kernel(psf_, geometry_, 40, 30, 2);
  KernelCacheOutcome outcome = KernelCacheOutcome::not_kept;
  const DisplayKernel first = cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0, &outcome);
  EXPECT_EQ(outcome, KernelCacheOutcome::stored);
  const std::string path = kernel_cache_entry_path(psf_, geometry_, 40, 30);
  EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
  const DisplayKernel second = cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0, &outcome);
  EXPECT_EQ(outcome, KernelCacheOutcome::read);
  EXPECT_TRUE(same_values(first, direct));
  EXPECT_TRUE(same_values(second, direct));
  // Another input, another entry: the age changes the kernel.
  const AnalyticPsf older = AnalyticPsf::cie(ObserverEye{70.0, 0.3});
  EXPECT_NE(kernel_cache_entry_path(older, geometry_, 40, 30), path);
  EXPECT_NE(kernel_cache_entry_path(psf_, DisplayGeometry{600.0, 0.3}, 40, 30), path);
  EXPECT_NE(kernel_cache_entry_path(psf_, geometry_, 40, 31), path);
  // Small kernels are not kept by default; other models never.
  cached_analytic_display_kernel(psf_, geometry_, 10, 10, 2, kCachedKernelMinimumPixels, &outcome);
  EXPECT_EQ(outcome, KernelCacheOutcome::not_kept);
  cached_analytic_display_kernel(AnalyticPsf::spencer(SpencerRegime::photopic, 0.0, ObserverEye{}), geometry_, 40, 30, 2, 0,
                                 &outcome);
  EXPECT_EQ(outcome, KernelCacheOutcome::not_kept);
}

TEST_F(KernelCache, ADamagedEntryIsDetectedAndIntegratedAgain) {
  const DisplayKernel direct = analytic_display_kernel(psf_, geometry_, 40, 30, 2);
  cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0);
  const std::string path = kernel_cache_entry_path(psf_, geometry_, 40, 30);
  const auto size = std::filesystem::file_size(path);
  for (const std::string& damage : {std::string("flip"), std::string("truncate")}) {
    if (damage == "flip") {
      std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
      file.seekg(static_cast<std::streamoff>(size / 2));
      char byte = 0;
      file.read(&byte, 1);
      byte = static_cast<char>(byte ^ 0x10);  // one bit of one value
      file.seekp(static_cast<std::streamoff>(size / 2));
      file.write(&byte, 1);
    } else {
      std::filesystem::resize_file(path, size - 100);
    }
    KernelCacheOutcome outcome = KernelCacheOutcome::not_kept;
    ::testing::internal::CaptureStderr();
    const DisplayKernel again = cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0, &outcome);
    const std::string warning = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(outcome, KernelCacheOutcome::recomputed) << damage;
    EXPECT_NE(warning.find("checksum mismatch"), std::string::npos) << warning;
    EXPECT_NE(warning.find(path), std::string::npos) << warning;
    EXPECT_TRUE(same_values(again, direct)) << damage;
    // Written again whole: the next read takes it.
    EXPECT_EQ(std::filesystem::file_size(path), size);
    cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0, &outcome);
    EXPECT_EQ(outcome, KernelCacheOutcome::read) << damage;
  }
}

TEST_F(KernelCache, AnEntryThatIsASymbolicLinkIsNotReadNorWrittenThrough) {
  const std::string path = kernel_cache_entry_path(psf_, geometry_, 40, 30);
  const std::filesystem::path target = scratch_.path() / "elsewhere.kernel";
  { std::ofstream(target) << "not a kernel"; }
  std::filesystem::create_symlink(target, path);
  KernelCacheOutcome outcome = KernelCacheOutcome::not_kept;
  ::testing::internal::CaptureStderr();
  const DisplayKernel kernel = cached_analytic_display_kernel(psf_, geometry_, 40, 30, 2, 0, &outcome);
  const std::string warning = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(outcome, KernelCacheOutcome::recomputed);
  EXPECT_NE(warning.find("symbolic link"), std::string::npos) << warning;
  EXPECT_TRUE(same_values(kernel, analytic_display_kernel(psf_, geometry_, 40, 30, 2)));
  // The link was replaced by the entry; its target is untouched.
  EXPECT_FALSE(std::filesystem::is_symlink(path));
  std::ifstream in(target);
  std::string text;
  std::getline(in, text);
  EXPECT_EQ(text, "not a kernel");
}

// Two sessions of the default eye on a display large enough for the cache: the second reads the
// far field's kernel and glares its frames bit for bit as the first did.
TEST_F(KernelCache, ASecondSessionGetsIdenticalFramesFromTheCache) {
  DisplaySpec display;
  display.width_px = 320;  // a 639 x 479 kernel: above kCachedKernelMinimumPixels
  display.height_px = 240;
  GlareSpec spec;
  spec.grid_px = 128;
  spec.wavelength_samples = 8;
  ImageRGBA frame(display.width_px, display.height_px, 0.2f);
  for (int y = 100; y < 104; ++y)
    for (int x = 150; x < 154; ++x)
      for (int c = 0; c < 3; ++c) frame.pixel(x, y)[c] = 6000.0f;
  ImageRGBA frames[2];
  for (int session = 0; session < 2; ++session) {
    GlareStage stage(spec, display, 11);
    frames[session] = stage.apply(frame, GlareMode::dynamic, 0.25);
    EXPECT_EQ(stage.analytic_for(GlareModel::human, display.width_px, display.height_px).kernels_from_cache(), session);
  }
  ASSERT_EQ(frames[0].rgba.size(), frames[1].rgba.size());
  EXPECT_EQ(std::memcmp(frames[0].rgba.data(), frames[1].rgba.data(), frames[0].rgba.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace glarelab
