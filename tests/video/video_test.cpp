#include "canopy/video/video.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "canopy/common/error.h"
#include "canopy/common/process.h"

namespace canopy::video {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Image<Rgb8> frame(int w, int h, std::uint8_t shade) {
  Image<Rgb8> img(w, h);
  for (auto& p : img.data) p = Rgb8{shade, static_cast<std::uint8_t>(255 - shade), 40};
  return img;
}

// Puts a fake `ffmpeg` first on PATH for the lifetime of the object.
class FakeEncoder {
 public:
  // `name`: a folder of its own (tests run in parallel processes).
  FakeEncoder(const std::string& name, const std::string& script)
      : dir_(fresh_dir(name)), old_path_(getenv("PATH")) {
    const fs::path exe = dir_ / "ffmpeg";
    std::ofstream(exe) << "#!/bin/sh\n" << script << "\n";
    fs::permissions(exe, fs::perms::owner_all);
    setenv("PATH", (dir_.string() + ":" + old_path_).c_str(), 1);
  }
  ~FakeEncoder() { setenv("PATH", old_path_.c_str(), 1); }

 private:
  fs::path dir_;
  std::string old_path_;
};

TEST(VideoWriter, ValidateOutputPathNamesThePath) {
  const fs::path d = fresh_dir("video_paths");
  EXPECT_NO_THROW(VideoWriter::validate_output_path((d / "ok.mp4").string()));
  EXPECT_FALSE(fs::exists(d / "ok.mp4.partial.mp4"));  // the probe file is removed
  auto message = [](const std::string& path) {
    try {
      VideoWriter::validate_output_path(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = (d / "no_such_folder" / "v.mp4").string();
  EXPECT_NE(message(missing).find(missing), std::string::npos) << message(missing);
  EXPECT_NE(message(missing).find("does not exist"), std::string::npos);
  EXPECT_NE(message(d.string()).find("is a folder"), std::string::npos);
  // A folder nobody may create files in (/proc refuses even root).
  EXPECT_NE(message("/proc/canopy_video_test.mp4").find("cannot write '/proc/canopy_video_test.mp4'"),
            std::string::npos);
  EXPECT_NE(message("").find("empty"), std::string::npos);
}

TEST(VideoWriter, EncoderThatDiesIsReportedNotFatal) {
  const fs::path d = fresh_dir("video_dies");
  const std::string path = (d / "run.mp4").string();
  FakeEncoder encoder("fake_ffmpeg_dies", "head -c 5000 > /dev/null; exit 7");
  VideoWriter video(path, 64, 48, 25.0);
  EXPECT_TRUE(video.ok());
  for (int i = 0; i < 50; ++i) video.write(frame(64, 48, static_cast<std::uint8_t>(i)));  // never throws
  video.flush();  // the failure is noticed by then
  EXPECT_FALSE(video.ok());
  EXPECT_NE(video.error().find("exited with code 7"), std::string::npos) << video.error();
  EXPECT_LT(video.frames(), 50);
  EXPECT_FALSE(video.close());
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial.mp4"));
}

TEST(VideoWriter, EncoderFailingAtTheEndIsReported) {
  const fs::path d = fresh_dir("video_fails_late");
  const std::string path = (d / "run.mp4").string();
  FakeEncoder encoder("fake_ffmpeg_fails_late", "cat > /dev/null; exit 1");
  VideoWriter video(path, 64, 48, 25.0);
  for (int i = 0; i < 5; ++i) video.write(frame(64, 48, 10));
  video.flush();
  EXPECT_EQ(video.frames(), 5);
  EXPECT_FALSE(video.close());
  EXPECT_NE(video.error().find("exited with code 1"), std::string::npos) << video.error();
  EXPECT_FALSE(fs::exists(path));
}

// Frames go to the encoder through the writer's queue (more frames than it holds, to a reader
// that starts late): all of them, whole and in order.
TEST(VideoWriter, EveryFrameReachesTheEncoderInOrder) {
  const fs::path d = fresh_dir("video_queue");
  const std::string path = (d / "run.mp4").string();
  const fs::path raw = d / "stream.raw";
  // The fake encoder keeps what it reads and writes an empty output file (its last argument).
  FakeEncoder encoder("fake_ffmpeg_keeps", "for a; do out=$a; done; sleep 0.2; cat > '" + raw.string() + "'; : > \"$out\"");
  constexpr int kFrames = 30;
  std::string expected;
  {
    VideoWriter video(path, 64, 48, 25.0);
    for (int i = 0; i < kFrames; ++i) {
      const Image<Rgb8> f = frame(64, 48, static_cast<std::uint8_t>(7 * i));
      for (const Rgb8& p : f.data) expected += {char(p.b), char(p.g), char(p.r)};  // ffmpeg reads bgr24
      video.write(f);
    }
    EXPECT_TRUE(video.close()) << video.error();
    EXPECT_EQ(video.frames(), kFrames);
  }
  std::ifstream in(raw, std::ios::binary);
  const std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(got.size(), expected.size());
  EXPECT_TRUE(got == expected);
  EXPECT_TRUE(fs::exists(path));
}

TEST(VideoWriter, WritesAPlayableFileWithRealFfmpeg) {
  if (!run_process({"sh", "-c", "command -v ffmpeg > /dev/null"}).ok()) GTEST_SKIP() << "ffmpeg not installed";
  const fs::path d = fresh_dir("video_real");
  const std::string path = (d / "it's a \"video\".mp4").string();  // quotes reach ffmpeg as text
  {
    VideoWriter video(path, 64, 48, 25.0);
    for (int i = 0; i < 10; ++i) video.write(frame(64, 48, static_cast<std::uint8_t>(20 * i)));
    EXPECT_TRUE(video.close()) << video.error();
    EXPECT_EQ(video.frames(), 10);
  }
  ASSERT_TRUE(fs::exists(path));
  EXPECT_GT(fs::file_size(path), 100u);
  EXPECT_FALSE(fs::exists(path + ".partial.mp4"));
}

// The colours survive the trip (the frames go to ffmpeg as BGR, and it is told so): an orange
// frame decodes orange, within what H.264's 4:2:0 YUV rounds.
TEST(VideoWriter, ColoursReachTheFileUnswapped) {
  if (!run_process({"sh", "-c", "command -v ffmpeg > /dev/null"}).ok()) GTEST_SKIP() << "ffmpeg not installed";
  const fs::path d = fresh_dir("video_colour");
  const std::string path = (d / "orange.mp4").string();
  const Rgb8 orange{230, 120, 20};
  {
    VideoWriter video(path, 64, 48, 25.0);
    Image<Rgb8> f(64, 48);
    for (auto& p : f.data) p = orange;
    for (int i = 0; i < 5; ++i) video.write(f);
    ASSERT_TRUE(video.close()) << video.error();
  }
  const fs::path raw = d / "first.rgb";
  ASSERT_TRUE(run_process({"ffmpeg", "-loglevel", "error", "-y", "-i", path, "-frames:v", "1", "-f", "rawvideo",
                           "-pix_fmt", "rgb24", raw.string()})
                  .ok());
  std::ifstream in(raw, std::ios::binary);
  const std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(got.size(), 64u * 48u * 3u);
  const std::size_t mid = 3 * (24 * 64 + 32);
  EXPECT_NEAR(static_cast<unsigned char>(got[mid]), orange.r, 6);
  EXPECT_NEAR(static_cast<unsigned char>(got[mid + 1]), orange.g, 6);
  EXPECT_NEAR(static_cast<unsigned char>(got[mid + 2]), orange.b, 6);
}

// The chase camera holds still while the base jitters within its dead band (3 mm, 3 mrad, also
// across the rounding steps of chase_pose and across yaw = +-pi), and follows a base that leaves it.
TEST(ChaseCamera, HoldsWithinTheDeadBandAndFollowsBeyondIt) {
  const BasePose camera{1.0005, 0.0, M_PI - 0.001};
  for (const BasePose& jitter : {BasePose{1.0025, 0.0, M_PI - 0.001}, BasePose{1.0, 0.002, M_PI - 0.0035},
                                 BasePose{1.0005, 0.0, -M_PI + 0.0015}}) {
    const BasePose held = chase_camera_base(camera, jitter);
    EXPECT_TRUE(chase_pose(held).isApprox(chase_pose(camera), 0.0)) << jitter.x_m << " " << jitter.yaw_rad;
  }
  for (const BasePose& moved : {BasePose{1.0040, 0.0, M_PI - 0.001}, BasePose{1.0005, 0.0, M_PI - 0.0045},
                                BasePose{1.0005, 0.0, -M_PI + 0.0025}}) {
    const BasePose followed = chase_camera_base(camera, moved);
    EXPECT_EQ(followed.x_m, moved.x_m);
    EXPECT_EQ(followed.yaw_rad, moved.yaw_rad);
  }
}

}  // namespace
}  // namespace canopy::video
