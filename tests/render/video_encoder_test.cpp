// MP4 encoder, checked with ffprobe/ffmpeg as an independent oracle: codec, pixel format,
// frame count, frame rate, time base and every frame's pts; odd sizes; an interrupted encode
// still plays; the same frames give the same bytes.
#include "render/output/video_encoder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "render_test_util.h"
#include "sim/core/error.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// A moving diagonal band on a gradient: every frame different, compressible.
Image syntheticFrame(int w, int h, int k) {
  Image image(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      const bool band = ((x + y + 3 * k) / 6) % 4 == 0;
      p[0] = static_cast<std::uint8_t>(band ? 230 : 40 + 2 * x);
      p[1] = static_cast<std::uint8_t>(band ? 200 : 60 + 3 * y);
      p[2] = static_cast<std::uint8_t>(band ? 40 : 120);
    }
  }
  return image;
}

struct Probe {
  std::map<std::string, std::string> stream;
  std::vector<long> pts;
  bool ok = false;
  std::string raw;
};

// ffprobe's view of the first video stream and of every decoded frame.
Probe probe(const std::string& path) {
  Probe p;
  int code = -1;
  p.raw = test::runCommand(
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=codec_name,pix_fmt,width,height,r_frame_rate,time_base,nb_read_frames,"
      "color_space:frame=pts:format_tags -of default=noprint_wrappers=1 '" +
          path + "' 2>&1",
      &code);
  p.ok = code == 0;
  std::istringstream lines(p.raw);
  std::string line;
  while (std::getline(lines, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "pts") {
      p.pts.push_back(std::stol(value));
    } else {
      p.stream[key] = value;
    }
  }
  return p;
}

VideoSettings settings(int w, int h, double fps) {
  VideoSettings s;
  s.width = w;
  s.height = h;
  s.fps = fps;
  s.crf = 18;
  return s;
}

bool haveFfprobe() { return std::system("ffprobe -version > /dev/null 2>&1") == 0; }

TEST(VideoEncoder, FfprobeSeesH264Yuv420pWithFramePts) {
  if (!haveFfprobe()) GTEST_SKIP() << "ffprobe not installed";
  test::ScratchDir dir("mp4_basic");
  const std::string path = dir.file("clip.mp4");
  const int n = 12;
  {
    VideoEncoder encoder(path, settings(64, 48, 24), replaceOutputs());
    for (int k = 0; k < n; ++k) encoder.write(k, syntheticFrame(64, 48, k));
    EXPECT_EQ(test::partialFiles(dir.path()), 1);  // written under the temporary name...
    EXPECT_FALSE(fs::exists(path));
    encoder.finish();
  }
  EXPECT_EQ(test::partialFiles(fs::path(path).parent_path()), 0);  // ...and renamed when complete
  const Probe p = probe(path);
  ASSERT_TRUE(p.ok) << p.raw;
  EXPECT_EQ(p.stream.at("codec_name"), "h264");
  EXPECT_EQ(p.stream.at("pix_fmt"), "yuv420p");
  EXPECT_EQ(p.stream.at("width"), "64");
  EXPECT_EQ(p.stream.at("height"), "48");
  EXPECT_EQ(p.stream.at("r_frame_rate"), "24/1");
  EXPECT_EQ(p.stream.at("time_base"), "1/24");
  EXPECT_EQ(p.stream.at("nb_read_frames"), std::to_string(n));
  EXPECT_EQ(p.stream.at("color_space"), "bt709");
  ASSERT_EQ(p.pts.size(), static_cast<std::size_t>(n)) << p.raw;
  for (int k = 0; k < n; ++k) EXPECT_EQ(p.pts[static_cast<std::size_t>(k)], k);
  // No wall-clock metadata.
  EXPECT_EQ(p.raw.find("creation_time"), std::string::npos) << p.raw;
  // +faststart: the index (moov) comes before the media data (mdat).
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_NE(bytes.find("moov"), std::string::npos);
  EXPECT_LT(bytes.find("moov"), bytes.find("mdat"));
}

TEST(VideoEncoder, FrameRangeKeepsSimulationTimestamps) {
  if (!haveFfprobe()) GTEST_SKIP() << "ffprobe not installed";
  // --frames 30:35 at 30 fps: frame k is still shown at t = k / 30.
  test::ScratchDir dir("mp4_range");
  const std::string path = dir.file("clip.mp4");
  {
    VideoEncoder encoder(path, settings(32, 32, 30), replaceOutputs());
    for (int k = 30; k <= 35; ++k) encoder.write(k, syntheticFrame(32, 32, k));
    encoder.finish();
  }
  const Probe p = probe(path);
  ASSERT_TRUE(p.ok) << p.raw;
  EXPECT_EQ(p.stream.at("time_base"), "1/30");
  ASSERT_EQ(p.pts.size(), 6u) << p.raw;
  for (int i = 0; i < 6; ++i) EXPECT_EQ(p.pts[static_cast<std::size_t>(i)], 30 + i);
}

TEST(VideoEncoder, OddSizesAreRejectedAndLeaveNoFile) {
  test::ScratchDir dir("mp4_odd");
  const std::string path = dir.file("clip.mp4");
  for (auto [w, h] : {std::pair{63, 48}, std::pair{64, 47}}) {
    try {
      VideoEncoder encoder(path, settings(w, h, 30), replaceOutputs());
      ADD_FAILURE() << w << "x" << h << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("even"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(test::partialFiles(fs::path(path).parent_path()), 0);
}

TEST(VideoEncoder, UnwritableFolderIsAClearError) {
  test::ScratchDir dir("mp4_unwritable");
  std::ofstream(dir.file("plain_file")) << "x";  // a "folder" that is a regular file
  const std::string path = dir.file("plain_file/clip.mp4");
  try {
    VideoEncoder encoder(path, settings(32, 32, 30), replaceOutputs());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), path);
  }
}

TEST(VideoEncoder, InterruptedEncodeLeavesAPlayableFile) {
  if (!haveFfprobe()) GTEST_SKIP() << "ffprobe not installed";
  test::ScratchDir dir("mp4_interrupted");
  const std::string path = dir.file("clip.mp4");
  try {
    VideoEncoder encoder(path, settings(48, 32, 25), replaceOutputs());
    for (int k = 0; k < 5; ++k) encoder.write(k, syntheticFrame(48, 32, k));
    throw std::runtime_error("simulated failure after 5 frames");  // unwinds past finish()
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(test::partialFiles(fs::path(path).parent_path()), 0);
  const Probe p = probe(path);
  ASSERT_TRUE(p.ok) << p.raw;
  EXPECT_EQ(p.stream.at("nb_read_frames"), "5");
  EXPECT_EQ(p.pts, (std::vector<long>{0, 1, 2, 3, 4}));
  // Nothing written at all: nothing left behind.
  const std::string empty = dir.file("empty.mp4");
  { VideoEncoder encoder(empty, settings(48, 32, 25), replaceOutputs()); }
  EXPECT_FALSE(fs::exists(empty));
  EXPECT_EQ(test::partialFiles(dir.path()), 0);
}

TEST(VideoEncoder, SameFramesGiveIdenticalBytes) {
  test::ScratchDir dir("mp4_determinism");
  auto encode = [&](const std::string& name) {
    const std::string path = dir.file(name);
    VideoEncoder encoder(path, settings(64, 64, 30), replaceOutputs());
    for (int k = 0; k < 20; ++k) encoder.write(k, syntheticFrame(64, 64, k));
    encoder.finish();
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string a = encode("a.mp4"), b = encode("b.mp4");
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b) << "two encodes of the same frames differ";
}

TEST(VideoEncoder, DecodedColoursMatchTheInput) {
  if (!haveFfprobe()) GTEST_SKIP() << "ffmpeg not installed";
  // A flat frame survives RGB -> BT.709 limited-range YUV -> RGB (ffmpeg decodes with the
  // stream's colour tags). Tolerance 3 of 255: 8-bit YUV quantisation steps are ~1.16 RGB
  // codes each way, plus x264 at crf 18 on a flat picture; a wrong matrix or range is off by 10+.
  test::ScratchDir dir("mp4_colour");
  const std::string path = dir.file("flat.mp4");
  Image flat(32, 32);
  for (int i = 0; i < 32 * 32; ++i) {
    flat.rgb[static_cast<std::size_t>(3 * i)] = 200;
    flat.rgb[static_cast<std::size_t>(3 * i + 1)] = 120;
    flat.rgb[static_cast<std::size_t>(3 * i + 2)] = 60;
  }
  {
    VideoEncoder encoder(path, settings(32, 32, 30), replaceOutputs());
    encoder.write(0, flat);
    encoder.finish();
  }
  const std::string raw = test::runCommand("ffmpeg -v error -i '" + path +
                                           "' -frames:v 1 -f rawvideo -pix_fmt rgb24 -");
  ASSERT_EQ(raw.size(), 32u * 32 * 3);
  const auto at = [&](int i) { return static_cast<int>(static_cast<unsigned char>(raw[i])); };
  const int centre = (16 * 32 + 16) * 3;
  EXPECT_NEAR(at(centre), 200, 3);
  EXPECT_NEAR(at(centre + 1), 120, 3);
  EXPECT_NEAR(at(centre + 2), 60, 3);
}

}  // namespace
}  // namespace vf
