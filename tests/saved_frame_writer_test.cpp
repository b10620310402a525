// The saved frames' writer (runner/session/saved_frame_writer.h): every frame handed over is on
// disk, equal to what was handed over, once finish() returns or the writer is gone; a stimulus
// frame loses only its round-off below 0, a display's drive values nothing; a failed write is
// raised on the session's thread at its next hand-over or at finish(), naming the file, and ends
// nothing else. Checked against the files read back (core/exr_io.h), never against timing.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/exr_io.h"
#include "runner/session/saved_frame_writer.h"
#include "scratch_dir.h"

namespace glarelab {
namespace {

namespace fs = std::filesystem;

// A frame whose values name it: pixel (x, y) of frame k holds k + x / 100 + y / 10000 in red,
// twice that in green, its negative in blue (a drive frame would hold none; the writer leaves it).
ImageRGBA numbered_frame(int k) {
  ImageRGBA frame(16, 8);
  for (int y = 0; y < frame.height_px; ++y)
    for (int x = 0; x < frame.width_px; ++x) {
      const float value = static_cast<float>(k) + static_cast<float>(x) / 100.0f + static_cast<float>(y) / 10000.0f;
      float* pixel = frame.pixel(x, y);
      pixel[0] = value;
      pixel[1] = 2.0f * value;
      pixel[2] = -value;
      pixel[3] = 1.0f;
    }
  return frame;
}

TEST(SavedFrameWriter, EveryFrameHandedOverIsOnDiskAsItWasAfterFinish) {
  const test::ScratchDir scratch;
  SavedFrameWriter writer;
  constexpr int kFrames = 3 * static_cast<int>(SavedFrameWriter::kQueuedFrames);  // more than the queue holds
  for (int k = 0; k < kFrames; ++k)
    writer.write((scratch.path() / ("frame_" + std::to_string(k) + ".exr")).string(), numbered_frame(k),
                 /*as_scene=*/false);
  writer.finish();
  for (int k = 0; k < kFrames; ++k) {
    const ImageRGBA read = read_exr((scratch.path() / ("frame_" + std::to_string(k) + ".exr")).string()).image;
    EXPECT_EQ(read.rgba, numbered_frame(k).rgba) << "frame " << k;
  }
  // No temporary file is left beside them.
  int files = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(scratch.path())) {
    EXPECT_EQ(entry.path().extension(), ".exr") << entry.path();
    ++files;
  }
  EXPECT_EQ(files, kFrames);
}

// A stimulus frame is written so that it loads as a scene: a channel below 0 by round-off (at most
// 1e-4 of the frame's peak, stimuli/scene_library.h) is 0 in the file, a deeper one is kept.
TEST(SavedFrameWriter, AStimulusFrameLosesOnlyItsRoundOffBelowZero) {
  const test::ScratchDir scratch;
  ImageRGBA frame(4, 1, 0.0f);
  frame.pixel(0, 0)[0] = 200.0f;    // the peak
  frame.pixel(1, 0)[1] = -2e-5f;    // FFT round-off: 1e-7 of the peak
  frame.pixel(2, 0)[2] = -0.5f;     // 2.5e-3 of the peak: a fault, kept
  frame.pixel(3, 0)[0] = 3.25f;
  for (int x = 0; x < 4; ++x) frame.pixel(x, 0)[3] = 1.0f;
  {
    SavedFrameWriter writer;
    writer.write((scratch.path() / "scene.exr").string(), frame, /*as_scene=*/true);
    writer.write((scratch.path() / "drive.exr").string(), frame, /*as_scene=*/false);
    writer.finish();
  }
  ImageRGBA expected = frame;
  expected.pixel(1, 0)[1] = 0.0f;
  EXPECT_EQ(read_exr((scratch.path() / "scene.exr").string()).image.rgba, expected.rgba);
  EXPECT_EQ(read_exr((scratch.path() / "drive.exr").string()).image.rgba, frame.rgba);
}

// A session that ends early (an exception, an abort) never calls finish(): the frames it read back
// are written all the same when the writer goes.
TEST(SavedFrameWriter, FramesStillQueuedWhenTheWriterGoesAreWritten) {
  const test::ScratchDir scratch;
  constexpr int kFrames = static_cast<int>(SavedFrameWriter::kQueuedFrames) + 2;
  {
    SavedFrameWriter writer;
    for (int k = 0; k < kFrames; ++k)
      writer.write((scratch.path() / ("frame_" + std::to_string(k) + ".exr")).string(), numbered_frame(k),
                   /*as_scene=*/false);
  }
  for (int k = 0; k < kFrames; ++k)
    EXPECT_EQ(read_exr((scratch.path() / ("frame_" + std::to_string(k) + ".exr")).string()).image.rgba,
              numbered_frame(k).rgba)
        << "frame " << k;
}

// A write that fails (its folder gone) is raised once, naming the file, at finish() or the next
// hand-over; the frames after it are still written.
TEST(SavedFrameWriter, AFailedWriteIsRaisedOnTheSessionsThreadNamingTheFile) {
  const test::ScratchDir scratch;
  const std::string lost = (scratch.path() / "no_such_folder" / "trial_0003.exr").string();
  SavedFrameWriter writer;
  writer.write(lost, numbered_frame(3), /*as_scene=*/true);
  try {
    writer.finish();
    ADD_FAILURE() << "the failed write was not raised";
  } catch (const ImageError& error) {
    EXPECT_NE(std::string(error.what()).find(lost), std::string::npos) << error.what();
  }
  writer.write((scratch.path() / "trial_0004.exr").string(), numbered_frame(4), /*as_scene=*/true);
  EXPECT_NO_THROW(writer.finish());  // raised once
  EXPECT_EQ(read_exr((scratch.path() / "trial_0004.exr").string()).image.rgba, numbered_frame(4).rgba);
  // The failed frame left nothing behind: the folder holds the one frame written.
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(scratch.path())) names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"trial_0004.exr"});
}

}  // namespace
}  // namespace glarelab
