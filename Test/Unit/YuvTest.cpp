// YuvReader / YuvWriter: round trips, the byte layout on disk, seeking, short files and refusals.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "TestFormat.h"

#include "Common/Error.h"
#include "Common/Frame.h"
#include "Common/Yuv.h"
#include "TestPaths.h"

#if defined(__unix__)
#include <csignal>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace fs = std::filesystem;

namespace {

using test::makeFormat;

// Frame bytes computed here from the layout rules, not with FrameFormat::frameBytes().
uint64_t expectedFrameBytes(int width, int height, int bitDepth, vs::ChromaFormat chroma) {
  uint64_t chromaSamples = 0;
  if (chroma == vs::ChromaFormat::Yuv420) chromaSamples = uint64_t((width + 1) / 2) * uint64_t((height + 1) / 2);
  if (chroma == vs::ChromaFormat::Yuv444) chromaSamples = uint64_t(width) * uint64_t(height);
  return (uint64_t(width) * uint64_t(height) + 2 * chromaSamples) * (bitDepth > 8 ? 2 : 1);
}

// Random samples over the whole range of the bit depth, different for every seed.
vs::Frame randomFrame(const vs::FrameFormat& format, unsigned seed) {
  vs::Frame frame(format);
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> sample(0, format.maxValue());
  for (vs::Plane& plane : frame.planes)
    for (uint16_t& s : plane.samples) s = uint16_t(sample(random));
  return frame;
}

void writeBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  ASSERT_TRUE(file.good()) << path;
}

std::vector<uint8_t> readBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// The message of the InputError that `action` throws, or "" (and a test failure) when it throws none.
template <typename Action>
std::string inputErrorOf(Action action) {
  try {
    action();
  } catch (const vs::InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no vs::InputError thrown";
  return "";
}

const vs::ChromaFormat kAllChroma[] = {vs::ChromaFormat::Yuv400, vs::ChromaFormat::Yuv420, vs::ChromaFormat::Yuv444};

}  // namespace

TEST(YuvTest, RoundTripEveryChromaFormatBitDepthAndOddSize) {
  const fs::path dir = vs::test::scratchDir("yuv_roundtrip");
  const int sizes[][2] = {{7, 5}, {6, 4}, {13, 3}, {1, 1}, {2, 9}};
  for (vs::ChromaFormat chroma : kAllChroma) {
    for (int bitDepth : {8, 10, 16}) {
      for (const auto& size : sizes) {
        const vs::FrameFormat format = makeFormat(size[0], size[1], bitDepth, chroma);
        SCOPED_TRACE(std::string(vs::chromaFormatName(chroma)) + " " + std::to_string(bitDepth) + "-bit " +
                     std::to_string(size[0]) + "x" + std::to_string(size[1]));
        const fs::path path = dir / "roundtrip.yuv";
        std::vector<vs::Frame> frames;
        for (unsigned i = 0; i < 3; ++i) frames.push_back(randomFrame(format, 100 * i + unsigned(bitDepth)));
        {
          vs::YuvWriter writer(path.string(), format);
          for (const vs::Frame& frame : frames) writer.append(frame);
          EXPECT_EQ(writer.framesWritten(), 3);
          writer.commit();
        }
        const uint64_t frameBytes = expectedFrameBytes(size[0], size[1], bitDepth, chroma);
        EXPECT_EQ(fs::file_size(path), 3 * frameBytes);

        vs::YuvReader reader(path.string(), format);
        EXPECT_EQ(reader.frameCount(), 3);
        EXPECT_EQ(reader.trailingBytes(), 0u);
        vs::Frame frame;
        for (int i = 0; i < 3; ++i) {
          reader.read(i, frame);
          EXPECT_EQ(frame.format, format);
          EXPECT_TRUE(frame == frames[size_t(i)]) << "frame " << i;
        }
        if (chroma == vs::ChromaFormat::Yuv420) {
          EXPECT_EQ(frame.planes[1].width, (size[0] + 1) / 2);
          EXPECT_EQ(frame.planes[1].height, (size[1] + 1) / 2);
        }
      }
    }
  }
}

TEST(YuvTest, EightBitLayoutIsPlanarYThenUThenV) {
  const fs::path dir = vs::test::scratchDir("yuv_layout8");
  const vs::FrameFormat format = makeFormat(3, 3, 8, vs::ChromaFormat::Yuv420);  // chroma 2x2
  vs::Frame frame(format);
  for (size_t i = 0; i < 9; ++i) frame.planes[0].samples[i] = uint16_t(10 + i);
  for (size_t i = 0; i < 4; ++i) frame.planes[1].samples[i] = uint16_t(100 + i);
  for (size_t i = 0; i < 4; ++i) frame.planes[2].samples[i] = uint16_t(200 + i);
  const fs::path path = dir / "layout.yuv";
  {
    vs::YuvWriter writer(path.string(), format);
    writer.append(frame);
    writer.commit();
  }
  const std::vector<uint8_t> expected = {10, 11, 12, 13, 14, 15, 16, 17, 18, 100, 101, 102, 103, 200, 201, 202, 203};
  EXPECT_EQ(readBytes(path), expected);
}

TEST(YuvTest, SixteenBitLayoutIsLittleEndianByteByByte) {
  const fs::path dir = vs::test::scratchDir("yuv_layout16");
  const vs::FrameFormat format = makeFormat(2, 1, 10, vs::ChromaFormat::Yuv444);
  // Hand-made file: Y = 0x0301, 0x0002; U = 0x03ff, 0x0100; V = 0x0000, 0x0210.
  const std::vector<uint8_t> bytes = {0x01, 0x03, 0x02, 0x00, 0xff, 0x03, 0x00, 0x01, 0x00, 0x00, 0x10, 0x02};
  const fs::path handMade = dir / "hand.yuv";
  writeBytes(handMade, bytes);

  vs::YuvReader reader(handMade.string(), format);
  ASSERT_EQ(reader.frameCount(), 1);
  vs::Frame frame;
  reader.read(0, frame);
  EXPECT_EQ(frame.planes[0].samples, (std::vector<uint16_t>{0x0301, 0x0002}));
  EXPECT_EQ(frame.planes[1].samples, (std::vector<uint16_t>{0x03ff, 0x0100}));
  EXPECT_EQ(frame.planes[2].samples, (std::vector<uint16_t>{0x0000, 0x0210}));

  const fs::path written = dir / "written.yuv";
  {
    vs::YuvWriter writer(written.string(), format, {handMade.string()});
    writer.append(frame);
    writer.commit();
  }
  const std::vector<uint8_t> writtenBytes = readBytes(written);
  ASSERT_EQ(writtenBytes.size(), bytes.size());
  for (size_t i = 0; i < bytes.size(); ++i) EXPECT_EQ(writtenBytes[i], bytes[i]) << "byte " << i;

  // 16-bit: the full range, high byte second.
  const vs::FrameFormat format16 = makeFormat(1, 1, 16, vs::ChromaFormat::Yuv400);
  vs::Frame frame16(format16);
  frame16.planes[0].samples[0] = 0xfe12;
  const fs::path path16 = dir / "sixteen.yuv";
  {
    vs::YuvWriter writer(path16.string(), format16);
    writer.append(frame16);
    writer.commit();
  }
  EXPECT_EQ(readBytes(path16), (std::vector<uint8_t>{0x12, 0xfe}));
}

TEST(YuvTest, ReadSeeksToAnyFrame) {
  const fs::path dir = vs::test::scratchDir("yuv_seek");
  const vs::FrameFormat format = makeFormat(5, 3, 10, vs::ChromaFormat::Yuv420);
  const fs::path path = dir / "seek.yuv";
  std::vector<vs::Frame> frames;
  {
    vs::YuvWriter writer(path.string(), format);
    for (unsigned i = 0; i < 6; ++i) {
      frames.push_back(randomFrame(format, 7 + i));
      frames.back().planes[0].at(0, 0) = uint16_t(i);  // frames differ even where random samples agree
      writer.append(frames.back());
    }
    writer.commit();
  }
  vs::YuvReader reader(path.string(), format);
  ASSERT_EQ(reader.frameCount(), 6);
  vs::Frame frame;
  vs::Plane luma;
  for (int64_t index : {4, 0, 5, 2, 2, 1, 3}) {
    reader.read(index, frame);
    EXPECT_TRUE(frame == frames[size_t(index)]) << "frame " << index;
    reader.readLuma(index, luma);
    EXPECT_TRUE(luma == frames[size_t(index)].planes[0]) << "luma of frame " << index;
  }
}

TEST(YuvTest, ReadsFramesPastFourGibibytes) {
  // A sparse file: frame n sits at n * frameBytes > 2^32, which needs 64-bit offsets all the way.
  const fs::path dir = vs::test::scratchDir("yuv_large");
  const vs::FrameFormat format = makeFormat(64, 48, 8, vs::ChromaFormat::Yuv420);
  const uint64_t frameBytes = format.frameBytes();
  const int64_t index = int64_t((uint64_t(1) << 32) / frameBytes) + 3;
  const fs::path path = dir / "large.yuv";
  const vs::Frame expected = randomFrame(format, 42);
  {
    vs::YuvWriter writer(path.string(), format);
    writer.append(expected);
    writer.commit();
  }
  const std::vector<uint8_t> bytes = readBytes(path);
  std::error_code ec;
  fs::resize_file(path, uint64_t(index + 1) * frameBytes, ec);
  if (ec) GTEST_SKIP() << "cannot make a sparse file here: " << ec.message();
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(std::streamoff(uint64_t(index) * frameBytes));
    file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    ASSERT_TRUE(file.good());
  }
  vs::YuvReader reader(path.string(), format);
  EXPECT_EQ(reader.frameCount(), index + 1);
  vs::Frame frame;
  reader.read(index, frame);
  EXPECT_TRUE(frame == expected);
  reader.read(index - 1, frame);  // a hole: zeros
  EXPECT_EQ(frame.planes[0].at(10, 10), 0);
  fs::remove(path);
}

TEST(YuvTest, FrameCountIgnoresTrailingPartialFrameAndReadingItFails) {
  const fs::path dir = vs::test::scratchDir("yuv_partial");
  const vs::FrameFormat format = makeFormat(7, 5, 8, vs::ChromaFormat::Yuv420);
  const uint64_t frameBytes = expectedFrameBytes(7, 5, 8, vs::ChromaFormat::Yuv420);  // 35 + 2 * 12 = 59
  ASSERT_EQ(frameBytes, 59u);
  const fs::path path = dir / "view1.yuv";
  writeBytes(path, std::vector<uint8_t>(3 * frameBytes + 40, 77));  // frame 3: all of Y, part of U

  vs::YuvReader reader(path.string(), format);
  EXPECT_EQ(reader.frameCount(), 3);
  EXPECT_EQ(reader.trailingBytes(), 40u);
  vs::Frame frame;
  reader.read(2, frame);  // the last whole frame reads fine
  EXPECT_EQ(frame.planes[2].at(3, 2), 77);

  const std::string message = inputErrorOf([&] { reader.read(3, frame); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("frame 3 is incomplete: 19 of 59 bytes missing (file holds 3 whole frames)"),
            std::string::npos)
      << message;

  // The 35 luma bytes of frame 3 are there, but a partial frame is refused for luma too.
  vs::Plane luma;
  const std::string lumaMessage = inputErrorOf([&] { reader.readLuma(3, luma); });
  EXPECT_NE(lumaMessage.find("frame 3 is incomplete: 19 of 59 bytes missing"), std::string::npos) << lumaMessage;

  const std::string pastEnd = inputErrorOf([&] { reader.read(7, frame); });
  EXPECT_NE(pastEnd.find("frame 7"), std::string::npos) << pastEnd;
  EXPECT_NE(pastEnd.find("59 of 59 bytes missing"), std::string::npos) << pastEnd;

  // The reader still works after an error.
  reader.read(0, frame);
  EXPECT_EQ(frame.planes[0].at(6, 4), 77);
}

TEST(YuvTest, ShortFileErrorNamesFileFrameAndMissingBytes) {
  const fs::path dir = vs::test::scratchDir("yuv_short");
  const vs::FrameFormat format = makeFormat(6, 4, 10, vs::ChromaFormat::Yuv444);
  const uint64_t frameBytes = expectedFrameBytes(6, 4, 10, vs::ChromaFormat::Yuv444);  // 144
  const fs::path path = dir / "short.yuv";
  writeBytes(path, std::vector<uint8_t>(frameBytes - 1, 0));
  vs::YuvReader reader(path.string(), format);
  EXPECT_EQ(reader.frameCount(), 0);
  vs::Frame frame;
  const std::string message = inputErrorOf([&] { reader.read(0, frame); });
  EXPECT_EQ(message, path.string() + ": frame 0 is incomplete: 1 of " + std::to_string(frameBytes) +
                         " bytes missing (file holds 0 whole frames)");
}

TEST(YuvTest, MissingFileAndFolderAreInputErrors) {
  const fs::path dir = vs::test::scratchDir("yuv_missing");
  const vs::FrameFormat format = makeFormat(8, 8, 8, vs::ChromaFormat::Yuv420);
  const std::string missing = (dir / "nothere.yuv").string();
  const std::string message = inputErrorOf([&] { vs::YuvReader reader(missing, format); });
  EXPECT_NE(message.find(missing), std::string::npos) << message;
  EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;

  const std::string folderMessage = inputErrorOf([&] { vs::YuvReader reader(dir.string(), format); });
  EXPECT_NE(folderMessage.find("folder"), std::string::npos) << folderMessage;

  const std::string badFormat = inputErrorOf([&] { vs::YuvReader reader(missing, makeFormat(0, 8, 8, format.chroma)); });
  EXPECT_NE(badFormat.find("0x8"), std::string::npos) << badFormat;
  const std::string badDepth = inputErrorOf([&] { vs::YuvReader reader(missing, makeFormat(8, 8, 17, format.chroma)); });
  EXPECT_NE(badDepth.find("17"), std::string::npos) << badDepth;
}

TEST(YuvTest, SampleAboveBitDepthMaximumIsAnInputError) {
  const fs::path dir = vs::test::scratchDir("yuv_overflow");
  const vs::FrameFormat format = makeFormat(4, 2, 10, vs::ChromaFormat::Yuv420);  // chroma 2x1
  const fs::path path = dir / "bad.yuv";
  {
    vs::YuvWriter writer(path.string(), format);
    writer.append(randomFrame(format, 1));
    writer.append(randomFrame(format, 2));
    writer.commit();
  }
  // Frame 1, plane U, sample (1, 0) := 1024, one above the 10-bit maximum.
  std::vector<uint8_t> bytes = readBytes(path);
  const size_t offset = size_t(format.frameBytes()) + 2 * (8 + 1);
  bytes[offset] = 0x00;
  bytes[offset + 1] = 0x04;
  writeBytes(path, bytes);

  vs::YuvReader reader(path.string(), format);
  vs::Frame frame;
  reader.read(0, frame);
  const std::string message = inputErrorOf([&] { reader.read(1, frame); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("frame 1, plane U"), std::string::npos) << message;
  EXPECT_NE(message.find("1024"), std::string::npos) << message;
  EXPECT_NE(message.find("(x 1, y 0)"), std::string::npos) << message;
  // Only luma read: the bad chroma sample is never looked at.
  vs::Plane luma;
  EXPECT_NO_THROW(reader.readLuma(1, luma));
}

// Large frames of odd plane sizes (none a multiple of the in-place widening's block of 256 samples),
// each plane read into its own memory and 8-bit samples widened there, into a frame that held the
// other frame's samples before. (Until 2026-11-26, sixth round: frames larger than the reader's
// 256 KiB chunk.) The file is laid out here byte by byte, not by YuvWriter.
TEST(YuvTest, FramesLargerThanOneReadChunkReadWhole) {
  const fs::path dir = vs::test::scratchDir("yuv_chunks");
  for (const int bitDepth : {8, 12}) {
    const vs::FrameFormat format = makeFormat(401, 333, bitDepth, vs::ChromaFormat::Yuv420);  // chroma 201x167
    const int widths[3] = {401, 201, 201}, heights[3] = {333, 167, 167};
    const int bytesPerSample = bitDepth > 8 ? 2 : 1;
    std::mt19937 random{unsigned(bitDepth)};
    std::uniform_int_distribution<int> sample(0, (1 << bitDepth) - 1);
    std::vector<std::vector<uint16_t>> expected[2];
    std::vector<uint8_t> bytes;
    for (int f = 0; f < 2; ++f)
      for (int p = 0; p < 3; ++p) {
        expected[f].emplace_back();
        for (int i = 0; i < widths[p] * heights[p]; ++i) {
          const uint16_t value = uint16_t(sample(random));
          expected[f].back().push_back(value);
          bytes.push_back(uint8_t(value & 0xff));
          if (bytesPerSample == 2) bytes.push_back(uint8_t(value >> 8));
        }
      }
    ASSERT_EQ(bytes.size(), 2 * expectedFrameBytes(401, 333, bitDepth, vs::ChromaFormat::Yuv420));
    const fs::path path = dir / ("big" + std::to_string(bitDepth) + ".yuv");
    writeBytes(path, bytes);
    vs::YuvReader reader(path.string(), format);
    vs::Frame frame;
    vs::Plane luma;
    for (const int f : {1, 0}) {
      reader.read(f, frame);
      for (int p = 0; p < 3; ++p) EXPECT_EQ(frame.planes[p].samples, expected[f][size_t(p)]) << "frame " << f << " plane " << p;
      reader.readLuma(f, luma);
      EXPECT_EQ(luma.samples, expected[f][0]) << "frame " << f;
    }
    if (bitDepth == 8) continue;
    // The last sample of V of frame 1, in the file's last chunk, one above the maximum: named.
    bytes[bytes.size() - 2] = 0x00;
    bytes[bytes.size() - 1] = 0x10;
    writeBytes(path, bytes);
    vs::YuvReader damaged(path.string(), format);
    const std::string message = inputErrorOf([&] { damaged.read(1, frame); });
    EXPECT_NE(message.find("frame 1, plane V: sample 4096 at (x 200, y 166)"), std::string::npos) << message;
  }
}

// The writer packs and writes a frame through a chunk of at most 256 KiB: frames of several chunks,
// whose chunk boundaries fall inside planes (and inside no 16-bit word), give the bytes the layout
// rules give, built here sample by sample, one frame after the other, with and without Y4M headers.
TEST(YuvTest, FramesLargerThanOneWriteChunkWriteWhole) {
  const fs::path dir = vs::test::scratchDir("yuv_write_chunks");
  for (const int bitDepth : {8, 10})
    for (const bool y4m : {false, true}) {
      const vs::FrameFormat format = makeFormat(1001, 533, bitDepth, vs::ChromaFormat::Yuv420);  // chroma 501x267
      std::vector<uint8_t> expected;
      const fs::path path = dir / ("big" + std::to_string(bitDepth) + (y4m ? ".y4m" : ".yuv"));
      {
        vs::YuvWriter writer(path.string(), format);
        for (unsigned f = 0; f < 2; ++f) {
          const vs::Frame frame = randomFrame(format, 10 * f + unsigned(bitDepth));
          writer.append(frame);
          if (y4m) expected.insert(expected.end(), {'F', 'R', 'A', 'M', 'E', '\n'});
          for (const vs::Plane& plane : frame.planes)
            for (const uint16_t value : plane.samples) {
              expected.push_back(uint8_t(value & 0xff));
              if (bitDepth > 8) expected.push_back(uint8_t(value >> 8));
            }
        }
        writer.commit();
      }
      ASSERT_GT(expectedFrameBytes(1001, 533, bitDepth, vs::ChromaFormat::Yuv420), uint64_t(3) << 18);
      std::vector<uint8_t> bytes = readBytes(path);
      if (y4m) {  // the stream header, up to its newline, is the Y4M tests' business
        const auto newline = std::find(bytes.begin(), bytes.end(), uint8_t('\n'));
        ASSERT_NE(newline, bytes.end());
        bytes.erase(bytes.begin(), newline + 1);
      }
      ASSERT_EQ(bytes.size(), expected.size()) << path;
      EXPECT_TRUE(bytes == expected) << path;
    }
}

// A sequence reads the next frame ahead as its file bytes (readBytes) and unpacks them when the frame
// begins: the same samples as read() and readLuma(), the file's bytes of the frame (or its Y plane)
// and no more, in every chroma format, at 8 and 10 bits, raw and Y4M; a 10-bit sample above the
// maximum is the same error when it is unpacked.
TEST(YuvTest, BytesReadAheadUnpackToTheFrameRead) {
  const fs::path dir = vs::test::scratchDir("yuv_bytes");
  for (const vs::ChromaFormat chroma : kAllChroma)
    for (const int bitDepth : {8, 10})
      for (const bool y4m : {false, true}) {
        const vs::FrameFormat format = makeFormat(9, 7, bitDepth, chroma);
        const fs::path path = dir / ("f" + std::to_string(bitDepth) + (y4m ? ".y4m" : ".yuv"));
        const std::vector<vs::Frame> frames = {randomFrame(format, 7), randomFrame(format, 8), randomFrame(format, 9)};
        {
          vs::YuvWriter writer(path.string(), format);
          for (const vs::Frame& frame : frames) writer.append(frame);
          writer.commit();
        }
        vs::YuvReader reader(path.string(), format);
        std::vector<uint8_t> bytes;
        vs::Frame frame;
        vs::Plane luma;
        for (const int f : {2, 0, 1}) {
          reader.readBytes(f, false, bytes);
          EXPECT_EQ(bytes.size(), expectedFrameBytes(9, 7, bitDepth, chroma));
          reader.unpack(f, bytes, frame);
          EXPECT_TRUE(frame == frames[size_t(f)]) << path << " frame " << f;
          reader.readBytes(f, true, bytes);
          EXPECT_EQ(bytes.size(), uint64_t(9 * 7 * (bitDepth > 8 ? 2 : 1)));
          reader.unpackLuma(f, bytes, luma);
          EXPECT_TRUE(luma == frames[size_t(f)].planes[0]) << path << " frame " << f;
        }
        if (bitDepth == 8 || y4m) continue;
        // The last luma sample of frame 1 one above the maximum: the error read() gives.
        std::vector<uint8_t> file = readBytes(path);
        const size_t last = size_t(format.frameBytes()) + size_t(9 * 7 - 1) * 2;
        file[last] = 0x00;
        file[last + 1] = 0x04;
        writeBytes(path, file);
        vs::YuvReader damaged(path.string(), format);
        const std::string expected = inputErrorOf([&] { damaged.read(1, frame); });
        EXPECT_NE(expected.find("frame 1, plane Y: sample 1024 at (x 8, y 6)"), std::string::npos) << expected;
        damaged.readBytes(1, false, bytes);
        EXPECT_EQ(inputErrorOf([&] { damaged.unpack(1, bytes, frame); }), expected);
        damaged.readBytes(1, true, bytes);
        EXPECT_EQ(inputErrorOf([&] { damaged.unpackLuma(1, bytes, luma); }), expected);
      }
}

TEST(YuvTest, ReadLumaSkipsChroma) {
  const fs::path dir = vs::test::scratchDir("yuv_luma");
  const vs::FrameFormat format = makeFormat(7, 5, 16, vs::ChromaFormat::Yuv420);
  const fs::path path = dir / "depth.yuv";
  std::vector<vs::Frame> frames = {randomFrame(format, 5), randomFrame(format, 6)};
  {
    vs::YuvWriter writer(path.string(), format);
    for (const vs::Frame& frame : frames) writer.append(frame);
    writer.commit();
  }
  vs::YuvReader reader(path.string(), format);
  vs::Plane luma(1, 1);
  reader.readLuma(1, luma);
  EXPECT_EQ(luma.width, 7);
  EXPECT_EQ(luma.height, 5);
  EXPECT_TRUE(luma == frames[1].planes[0]);
  reader.readLuma(0, luma);
  EXPECT_TRUE(luma == frames[0].planes[0]);
}

TEST(YuvTest, WriterRefusesOutputThatIsAnInput) {
  const fs::path dir = vs::test::scratchDir("yuv_same");
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  const fs::path input = dir / "input.yuv";
  const std::vector<uint8_t> content(2 * format.frameBytes(), 33);
  writeBytes(input, content);
  fs::create_directory(dir / "sub");
  fs::create_symlink(input, dir / "link.yuv");

  const std::vector<std::string> spellings = {
      input.string(), (dir / "." / "input.yuv").string(), (dir / "sub" / ".." / "input.yuv").string(),
      (dir / "link.yuv").string()};
  for (const std::string& output : spellings) {
    const std::string message = inputErrorOf([&] {
      vs::YuvWriter writer(output, format, {"other.yuv", input.string()});
    });
    EXPECT_NE(message.find("same file as input"), std::string::npos) << output << ": " << message;
  }
  // The other way round: the input named through a different spelling.
  const std::string reverse = inputErrorOf([&] {
    vs::YuvWriter writer(input.string(), format, {(dir / "." / "sub" / ".." / "input.yuv").string()});
  });
  EXPECT_NE(reverse.find("same file as input"), std::string::npos) << reverse;
  EXPECT_EQ(readBytes(input), content) << "a refused output must leave the input untouched";

  // Neither file exists yet: the canonical spellings still match.
  const std::string planned = inputErrorOf([&] {
    vs::YuvWriter writer((dir / "new.yuv").string(), format, {(dir / "nosuch" / ".." / "new.yuv").string()});
  });
  EXPECT_NE(planned.find("same file as input"), std::string::npos) << planned;

  // A different file is fine.
  EXPECT_NO_THROW(vs::YuvWriter((dir / "output.yuv").string(), format, {input.string()}));
}

TEST(YuvTest, WriterRefusesMissingFolderAndFolderOutput) {
  const fs::path dir = vs::test::scratchDir("yuv_folder");
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  const fs::path missingFolder = dir / "nosuchfolder";
  const std::string message = inputErrorOf([&] {
    vs::YuvWriter writer((missingFolder / "out.yuv").string(), format);
  });
  EXPECT_NE(message.find("output folder"), std::string::npos) << message;
  EXPECT_NE(message.find(missingFolder.string()), std::string::npos) << message;
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(missingFolder));

  const std::string folderOutput = inputErrorOf([&] { vs::YuvWriter writer(dir.string(), format); });
  EXPECT_NE(folderOutput.find("is a folder"), std::string::npos) << folderOutput;

  writeBytes(dir / "plainfile", {1});
  const std::string fileAsFolder = inputErrorOf([&] {
    vs::YuvWriter writer((dir / "plainfile" / "out.yuv").string(), format);
  });
  EXPECT_NE(fileAsFolder.find("is not a folder"), std::string::npos) << fileAsFolder;
}

TEST(YuvTest, WriterRefusesReadOnlyFolder) {
#if defined(__unix__)
  if (geteuid() == 0) GTEST_SKIP() << "root writes into read-only folders";
#endif
  const fs::path dir = vs::test::scratchDir("yuv_readonly");
  fs::create_directory(dir / "locked");
  fs::permissions(dir / "locked", fs::perms::owner_read | fs::perms::owner_exec);
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  const std::string message = inputErrorOf([&] {
    vs::YuvWriter writer((dir / "locked" / "out.yuv").string(), format);
  });
  fs::permissions(dir / "locked", fs::perms::owner_all);
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
}

// The output is a temporary file until commit(): the previous file keeps its bytes while frames
// are written, and is replaced whole, with the new bytes only, by commit().
TEST(YuvTest, WriterReplacesExistingOutputOnlyOnCommit) {
  const fs::path dir = vs::test::scratchDir("yuv_replace");
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv400);
  const fs::path path = dir / "out.yuv";
  const std::vector<uint8_t> previous(1000, 9);
  writeBytes(path, previous);
  const vs::Frame frame = randomFrame(format, 3);
  {
    vs::YuvWriter writer(path.string(), format);
    writer.append(frame);
    EXPECT_EQ(readBytes(path), previous) << "the previous file is untouched until commit()";
    writer.commit();
  }
  std::vector<uint8_t> expected(frame.planes[0].samples.begin(), frame.planes[0].samples.end());
  EXPECT_EQ(readBytes(path), expected);
  // Without commit(): the file keeps what it held, and no temporary file is left.
  {
    vs::YuvWriter writer(path.string(), format);
    writer.append(randomFrame(format, 4));
  }
  EXPECT_EQ(readBytes(path), expected);
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u) << "a temporary file was left behind";
}

// A symbolic link output keeps pointing where it did: the file it names is replaced.
TEST(YuvTest, WriterReplacesTheFileALinkNames) {
  const fs::path dir = vs::test::scratchDir("yuv_link_output");
  const vs::FrameFormat format = makeFormat(2, 2, 8, vs::ChromaFormat::Yuv400);
  fs::create_directory(dir / "store");
  writeBytes(dir / "store" / "real.yuv", {1, 2, 3});
  fs::create_symlink(dir / "store" / "real.yuv", dir / "link.yuv");
  vs::YuvWriter writer((dir / "link.yuv").string(), format);
  vs::Frame frame(format);
  frame.fill(7);
  writer.append(frame);
  writer.commit();
  EXPECT_TRUE(fs::is_symlink(dir / "link.yuv"));
  EXPECT_EQ(readBytes(dir / "store" / "real.yuv"), (std::vector<uint8_t>{7, 7, 7, 7}));
}

// Y4M out: the header the format gives, "FRAME\n" before each frame; read back natively.
TEST(YuvTest, Y4mRoundTrip) {
  const fs::path dir = vs::test::scratchDir("yuv_y4m");
  for (vs::ChromaFormat chroma : kAllChroma)
    for (int bitDepth : {8, 10}) {
      const vs::FrameFormat format = makeFormat(6, 4, bitDepth, chroma);
      const fs::path path = dir / "out.y4m";
      std::vector<vs::Frame> frames = {randomFrame(format, 1), randomFrame(format, 2)};
      {
        vs::YuvWriter writer(path.string(), format);
        for (const vs::Frame& frame : frames) writer.append(frame);
        writer.commit();
      }
      const std::vector<uint8_t> bytes = readBytes(path);
      const std::string text(bytes.begin(), bytes.end());
      const std::string header = vs::formatY4mHeader(format);
      ASSERT_EQ(text.compare(0, header.size(), header), 0) << text.substr(0, 40);
      EXPECT_EQ(text.compare(header.size(), 6, "FRAME\n"), 0);
      EXPECT_EQ(bytes.size(), header.size() + 2 * (6 + format.frameBytes()));
      vs::YuvReader reader(path.string(), format);
      ASSERT_NE(reader.y4m(), nullptr);
      EXPECT_EQ(reader.frameCount(), 2);
      EXPECT_EQ(reader.trailingBytes(), 0u);
      vs::Frame frame;
      for (int i = 0; i < 2; ++i) {
        reader.read(i, frame);
        EXPECT_TRUE(frame == frames[size_t(i)]) << vs::describeFormat(format) << " frame " << i;
      }
      // The same file read with another format: refused, both formats named.
      vs::FrameFormat other = format;
      other.width = 8;
      const std::string message = inputErrorOf([&] { vs::YuvReader wrong(path.string(), other); });
      EXPECT_NE(message.find("the Y4M header says " + vs::describeFormat(format)), std::string::npos) << message;
      EXPECT_NE(message.find(vs::describeFormat(other)), std::string::npos) << message;
    }
}

// Headers written by hand, as other tools write them: parameters in any order, frame headers with
// parameters, the chroma tags of ffmpeg.
TEST(YuvTest, Y4mHeadersOfOtherTools) {
  const vs::Y4mHeader a = vs::parseY4mHeader("YUV4MPEG2 C420mpeg2 W688 H555 F30000:1001 Ib A0:0 XYSCSS=420MPEG2\n", "a");
  EXPECT_EQ(a.format.width, 688);
  EXPECT_EQ(a.format.height, 555);
  EXPECT_EQ(a.format.chroma, vs::ChromaFormat::Yuv420);
  EXPECT_EQ(a.format.bitDepth, 8);
  EXPECT_EQ(a.rateNumerator, 30000);
  EXPECT_EQ(a.rateDenominator, 1001);
  EXPECT_EQ(a.interlacing, 'b');
  const vs::Y4mHeader b = vs::parseY4mHeader("YUV4MPEG2 W4 H2 Cmono16\n", "b");
  EXPECT_EQ(b.format.chroma, vs::ChromaFormat::Yuv400);
  EXPECT_EQ(b.format.bitDepth, 16);
  EXPECT_EQ(b.headerBytes, 24u);
  const vs::Y4mHeader c = vs::parseY4mHeader("YUV4MPEG2 W4 H2 C444p12\n", "c");
  EXPECT_EQ(c.format.chroma, vs::ChromaFormat::Yuv444);
  EXPECT_EQ(c.format.bitDepth, 12);
  const vs::Y4mHeader d = vs::parseY4mHeader("YUV4MPEG2 W4 H2\n", "d");  // no C: 4:2:0 8-bit
  EXPECT_EQ(d.format.chroma, vs::ChromaFormat::Yuv420);
  EXPECT_NE(inputErrorOf([] { vs::parseY4mHeader("YUV4MPEG2 W4 H2 C422\n", "e"); }).find("C422 is not read"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { vs::parseY4mHeader("YUV4MPEG2 W4 C420\n", "f"); }).find("no H"), std::string::npos);
  EXPECT_NE(inputErrorOf([] { vs::parseY4mHeader("YUV4MPEG2 W4 H2 C420", "g"); }).find("no end of line"),
            std::string::npos);
  // A frame header with parameters is skipped whole.
  const fs::path dir = vs::test::scratchDir("yuv_y4m_params");
  const std::string file = std::string("YUV4MPEG2 W2 H2 Cmono\n") + "FRAME Ixyz\n" + "\x01\x02\x03\x04" +
                           "FRAME Ixyz\n" + "\x05\x06\x07\x08";
  writeBytes(dir / "p.y4m", std::vector<uint8_t>(file.begin(), file.end()));
  vs::YuvReader reader((dir / "p.y4m").string(), makeFormat(2, 2, 8, vs::ChromaFormat::Yuv400));
  ASSERT_EQ(reader.frameCount(), 2);
  vs::Frame frame;
  reader.read(1, frame);
  EXPECT_EQ(frame.planes[0].samples, (std::vector<uint16_t>{5, 6, 7, 8}));
}

// Images and videos are recognised by their first bytes, whatever their name, and refused with what
// they are and an ffmpeg command line.
TEST(YuvTest, ContainersAreRefusedWithAConversion) {
  const fs::path dir = vs::test::scratchDir("yuv_containers");
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  const std::pair<std::string, std::string> files[] = {
      {std::string("\x89PNG\r\n\x1a\n", 8) + std::string(40, '\0'), "a PNG image"},
      {std::string("\xff\xd8\xff\xe0", 4) + std::string(40, 'j'), "a JPEG image"},
      {std::string("\0\0\0\x20" "ftypisom", 12) + std::string(40, 'm'), "an MP4/MOV video"},
      {std::string("\x1a\x45\xdf\xa3", 4) + std::string(40, 'k'), "a Matroska/WebM video"},
      {"GIF89a" + std::string(40, 'g'), "a GIF image"}};
  for (const auto& [content, what] : files) {
    const fs::path path = dir / "view.yuv";
    writeBytes(path, std::vector<uint8_t>(content.begin(), content.end()));
    const std::string message = inputErrorOf([&] { vs::YuvReader reader(path.string(), format); });
    EXPECT_NE(message.find("the file is " + what + ", not a raw YUV"), std::string::npos) << message;
    EXPECT_NE(message.find("ffmpeg -i '" + path.string() + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("-pix_fmt yuv420p"), std::string::npos) << message;
  }
  // Raw bytes that only start like a BMP ("BM" without the file's size after it) are raw YUV.
  const std::string raw = "BM" + std::string(format.frameBytes() - 2, '\x10');
  writeBytes(dir / "raw.yuv", std::vector<uint8_t>(raw.begin(), raw.end()));
  EXPECT_NO_THROW(vs::YuvReader((dir / "raw.yuv").string(), format));
}

// Sizes that divide a file exactly, for the message of a file that is not whole frames: the
// configured width's neighbours first. Checked against frame sizes computed here.
TEST(YuvTest, WholeFrameSizesDivideTheFile) {
  const vs::FrameFormat art = makeFormat(680, 555 + 1, 8, vs::ChromaFormat::Yuv420);  // 688 x 556 file, 3 frames
  const uint64_t fileBytes = 3 * uint64_t(688 * 556 * 3 / 2);
  const std::string sizes = vs::wholeFrameSizes(fileBytes, art);
  EXPECT_EQ(sizes.rfind("width 688 (3 frames)", 0), 0u) << sizes;
  // Every suggested width divides the file.
  for (size_t at = sizes.find("width "); at != std::string::npos; at = sizes.find("width ", at + 1)) {
    const int width = std::stoi(sizes.substr(at + 6));
    vs::FrameFormat f = art;
    f.width = width;
    EXPECT_EQ(fileBytes % f.frameBytes(), 0u) << width;
  }
  EXPECT_EQ(vs::wholeFrameSizes(7, makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420)), "");
}

#if defined(__unix__)
// Past the file size limit (ulimit -f) the write fails with EFBIG (SIGXFSZ is ignored, not fatal):
// an InputError, no further frames, and nothing replaced.
TEST(YuvTest, FailedWriteReplacesNothing) {
  const fs::path dir = vs::test::scratchDir("yuv_writefail");
  const vs::FrameFormat format = makeFormat(8, 6, 10, vs::ChromaFormat::Yuv420);
  const uint64_t frameBytes = format.frameBytes();
  const fs::path path = dir / "out.yuv";
  const std::vector<uint8_t> previous(100, 1);
  writeBytes(path, previous);
  std::string message;
  {
    vs::YuvWriter writer(path.string(), format);
    rlimit saved{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
    if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < 5 * frameBytes) GTEST_SKIP() << "file size limit";
    rlimit limited = saved;
    limited.rlim_cur = rlim_t(2 * frameBytes + frameBytes / 2);
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limited), 0);
    writer.append(randomFrame(format, 1));
    writer.append(randomFrame(format, 2));
    try {
      writer.append(randomFrame(format, 3));
    } catch (const vs::InputError& error) {
      message = error.what();
    }
    setrlimit(RLIMIT_FSIZE, &saved);
    EXPECT_EQ(writer.framesWritten(), 2);
    const std::string again = inputErrorOf([&] { writer.append(randomFrame(format, 4)); });
    EXPECT_NE(again.find("earlier write failed"), std::string::npos) << again;
    const std::string commit = inputErrorOf([&] { writer.commit(); });
    EXPECT_NE(commit.find("not replaced"), std::string::npos) << commit;
  }
  EXPECT_NE(message.find("writing frame 2 failed"), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_EQ(readBytes(path), previous);
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 1u) << "a temporary file was left behind";
}

// A device is written in place (nothing to rename onto it); its write errors are InputErrors.
TEST(YuvTest, WriteToFullDeviceIsAnInputError) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  vs::YuvWriter writer("/dev/full", format);
  const std::string message = inputErrorOf([&] { writer.append(randomFrame(format, 1)); });
  EXPECT_NE(message.find("/dev/full: writing frame 0 failed"), std::string::npos) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

// A FIFO or a device named as an input is refused by stat() alone: open() on a FIFO without a
// writer would wait for ever.
TEST(YuvTest, FifoAndDeviceInputsAreRefusedWithoutOpening) {
  const fs::path dir = vs::test::scratchDir("yuv_fifo");
  const vs::FrameFormat format = makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420);
  ASSERT_EQ(mkfifo((dir / "pipe.yuv").c_str(), 0600), 0);
  const std::string fifo = inputErrorOf([&] { vs::YuvReader reader((dir / "pipe.yuv").string(), format); });
  EXPECT_NE(fifo.find("is a FIFO"), std::string::npos) << fifo;
  const std::string device = inputErrorOf([&] { vs::YuvReader reader("/dev/zero", format); });
  EXPECT_NE(device.find("is a device"), std::string::npos) << device;
}
#endif

TEST(YuvDeathTest, WriterChecksFormatAndSampleRange) {
  const fs::path dir = vs::test::scratchDir("yuv_death");
  const vs::FrameFormat format = makeFormat(4, 4, 10, vs::ChromaFormat::Yuv420);
  const std::string path = (dir / "out.yuv").string();
  EXPECT_DEATH(
      {
        vs::YuvWriter writer(path, format);
        writer.append(vs::Frame(makeFormat(4, 4, 8, vs::ChromaFormat::Yuv420)));
      },
      "format differs");
  EXPECT_DEATH(
      {
        vs::YuvWriter writer(path, format);
        vs::Frame frame(format);
        frame.fill(0);
        frame.planes[2].at(1, 1) = 1024;
        writer.append(frame);
      },
      "exceeds the bit depth's maximum");
}
