#include "Common/FileKind.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <vector>

#include "Common/Error.h"

namespace vs {

namespace {

std::string withRole(const std::string& role, const std::string& message) {
  return role.empty() ? message : role + ": " + message;
}

bool startsWith(const std::string& text, const char* prefix, size_t length) {
  return text.size() >= length && std::memcmp(text.data(), prefix, length) == 0;
}

uint32_t littleEndian32(const std::string& text, size_t at) {
  return uint32_t(uint8_t(text[at])) | uint32_t(uint8_t(text[at + 1])) << 8 | uint32_t(uint8_t(text[at + 2])) << 16 |
         uint32_t(uint8_t(text[at + 3])) << 24;
}

// ffmpeg's name of the raw pixel format that matches `format` (little-endian above 8 bits).
std::string ffmpegPixelFormat(const FrameFormat& format) {
  const std::string base = format.chroma == ChromaFormat::Yuv400   ? "gray"
                           : format.chroma == ChromaFormat::Yuv444 ? "yuv444p"
                                                                   : "yuv420p";
  if (format.bitDepth <= 8) return base;
  return base + std::to_string(format.bitDepth) + "le";
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

}  // namespace

void requireRegularFile(const std::string& path, const std::string& role) {
  if (path.empty()) throw InputError(withRole(role, "no file name given"));
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    throw InputError(withRole(role, path + ": cannot open: " + std::generic_category().message(error)));
  }
  const char* what = nullptr;
  if (S_ISDIR(info.st_mode)) what = "is a folder, not a file";
  else if (S_ISFIFO(info.st_mode))
    what = "is a FIFO (named pipe), not a regular file; sequences are read by frame offset";
  else if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) what = "is a device, not a regular file";
  else if (S_ISSOCK(info.st_mode)) what = "is a socket, not a regular file";
  else if (!S_ISREG(info.st_mode)) what = "is not a regular file";
  if (what) throw InputError(withRole(role, path + ": cannot open: " + what));
}

ContainerSniff sniffContainer(const std::string& head, uint64_t fileBytes, const std::string& path,
                              const FrameFormat& format) {
  ContainerSniff sniff;
  if (startsWith(head, "YUV4MPEG2", 9)) {
    sniff.kind = ContainerKind::Y4m;
    sniff.description = "a Y4M (YUV4MPEG2) sequence";
    return sniff;
  }
  const auto has = [&](size_t at, const char* bytes, size_t length) {
    return head.size() >= at + length && std::memcmp(head.data() + at, bytes, length) == 0;
  };
  bool image = true;  // one picture: ffmpeg reads it as one frame
  if (has(0, "\x89PNG\r\n\x1a\n", 8)) sniff.description = "a PNG image";
  else if (has(0, "\xff\xd8\xff", 3)) sniff.description = "a JPEG image";
  else if (has(0, "GIF87a", 6) || has(0, "GIF89a", 6)) sniff.description = "a GIF image";
  else if (has(0, "II*\0", 4) || has(0, "MM\0*", 4)) sniff.description = "a TIFF image";
  else if (has(0, "BM", 2) && head.size() >= 6 && littleEndian32(head, 2) == fileBytes)
    sniff.description = "a BMP image";  // raw bytes may start with "BM"; the size field must match too
  else if (has(0, "RIFF", 4) && has(8, "WEBP", 4)) sniff.description = "a WebP image";
  else if (has(0, "v/1\x01", 4)) sniff.description = "an OpenEXR image";
  else if ((has(0, "P5", 2) || has(0, "P6", 2)) && head.size() > 2 && isSpace(head[2]))
    sniff.description = has(0, "P5", 2) ? "a PGM image" : "a PPM image";
  else if (has(4, "ftyp", 4) && (has(8, "heic", 4) || has(8, "mif1", 4) || has(8, "avif", 4)))
    sniff.description = "a HEIF/AVIF image";
  else {
    image = false;
    if (has(4, "ftyp", 4)) sniff.description = "an MP4/MOV video";
    else if (has(0, "\x1a\x45\xdf\xa3", 4)) sniff.description = "a Matroska/WebM video";
    else if (has(0, "RIFF", 4) && has(8, "AVI ", 4)) sniff.description = "an AVI video";
    else if (has(0, "FLV\x01", 4)) sniff.description = "an FLV video";
    else if (has(0, "OggS", 4)) sniff.description = "an Ogg stream";
    else if (has(0, "\0\0\x01\xba", 4)) sniff.description = "an MPEG program stream";
    else if (has(0, "\x1f\x8b", 2)) sniff.description = "a gzip-compressed file";
    else if (has(0, "PK\x03\x04", 4)) sniff.description = "a ZIP archive";
    else return sniff;  // raw YUV (anything else)
  }
  sniff.kind = ContainerKind::Other;
  if (sniff.description == "a gzip-compressed file" || sniff.description == "a ZIP archive") {
    sniff.conversion = "unpack it first (gunzip or unzip), then name the .yuv file";
    return sniff;
  }
  std::filesystem::path target(path);
  target.replace_extension(".yuv");
  if (target == std::filesystem::path(path)) target = std::filesystem::path(path + ".yuv");
  const std::string pixelFormat = ffmpegPixelFormat(format);
  sniff.conversion = "ffmpeg -i '" + path + "' " + (image ? "-frames:v 1 " : "") + "-f rawvideo -pix_fmt " +
                     pixelFormat + " '" + target.string() + "'";
  return sniff;
}

Y4mHeader parseY4mHeader(const std::string& head, const std::string& path) {
  const size_t end = head.find('\n');
  if (!startsWith(head, "YUV4MPEG2", 9) || end == std::string::npos)
    throw InputError(path + ": Y4M stream header: no end of line within its first " + std::to_string(head.size()) +
                     " bytes (a cut or damaged file?)");
  Y4mHeader header;
  header.headerBytes = end + 1;
  header.format.width = header.format.height = 0;
  std::istringstream tokens(head.substr(9, end - 9));
  std::string chromaTag = "420jpeg";
  for (std::string token; tokens >> token;) {
    const char tag = token[0];
    const std::string value = token.substr(1);
    auto positive = [&](int& out) {
      char* stop = nullptr;
      const long v = std::strtol(value.c_str(), &stop, 10);
      if (value.empty() || *stop || v <= 0 || v > 1 << 20)
        throw InputError(path + ": Y4M stream header: '" + token + "': expected a positive whole number after " + tag);
      out = int(v);
    };
    switch (tag) {
      case 'W': positive(header.format.width); break;
      case 'H': positive(header.format.height); break;
      case 'C': chromaTag = value; break;
      case 'I': header.interlacing = value.empty() ? '?' : value[0]; break;
      case 'F': {
        const size_t colon = value.find(':');
        char* stop = nullptr;
        const long n = std::strtol(value.c_str(), &stop, 10);
        const long d = colon == std::string::npos ? 0 : std::strtol(value.c_str() + colon + 1, &stop, 10);
        if (colon == std::string::npos || n <= 0 || d <= 0)
          throw InputError(path + ": Y4M stream header: frame rate '" + token +
                           "': expected F<numerator>:<denominator>");
        header.rateNumerator = int(std::min(n, 1L << 30));
        header.rateDenominator = int(std::min(d, 1L << 30));
        break;
      }
      default: break;  // A (aspect), X (comments and extensions): nothing to read from them
    }
  }
  if (header.format.width == 0 || header.format.height == 0)
    throw InputError(path + ": Y4M stream header has no " +
                     std::string(header.format.width ? "H (height)" : "W (width)"));
  // Chroma tag: 420 (any siting), 444, mono, each with an optional pN / N bit depth.
  std::string family = chromaTag, depth;
  for (const char* name : {"420jpeg", "420mpeg2", "420paldv", "420p", "420", "444p", "444", "mono"})
    if (chromaTag.rfind(name, 0) == 0) {
      family = name;
      depth = chromaTag.substr(family.size());
      break;
    }
  header.format.bitDepth = 8;
  if (family.rfind("420", 0) == 0) header.format.chroma = ChromaFormat::Yuv420;
  else if (family.rfind("444", 0) == 0 && chromaTag.find("alpha") == std::string::npos)
    header.format.chroma = ChromaFormat::Yuv444;
  else if (family == "mono") header.format.chroma = ChromaFormat::Yuv400;
  else
    throw InputError(path + ": Y4M chroma format C" + chromaTag +
                     " is not read (4:2:0, 4:4:4 and mono are; convert with ffmpeg -pix_fmt yuv420p)");
  const bool numbered = family == "420p" || family == "444p" || family == "mono";
  if (!depth.empty()) {
    char* stop = nullptr;
    const long bits = std::strtol(depth.c_str(), &stop, 10);
    if (!numbered || *stop || bits < 8 || bits > 16)
      throw InputError(path + ": Y4M chroma format C" + chromaTag +
                       " is not read (8- to 16-bit 4:2:0, 4:4:4 and mono are)");
    header.format.bitDepth = int(bits);
  } else if (family == "420p" || family == "444p") {
    throw InputError(path + ": Y4M chroma format C" + chromaTag + ": bit depth missing");
  }
  return header;
}

std::string formatY4mHeader(const FrameFormat& format, int rateNumerator, int rateDenominator) {
  std::string chroma;
  const std::string bits = std::to_string(format.bitDepth);
  if (format.chroma == ChromaFormat::Yuv400) chroma = format.bitDepth > 8 ? "mono" + bits : "mono";
  else if (format.chroma == ChromaFormat::Yuv444) chroma = format.bitDepth > 8 ? "444p" + bits : "444";
  else chroma = format.bitDepth > 8 ? "420p" + bits : "420jpeg";
  return "YUV4MPEG2 W" + std::to_string(format.width) + " H" + std::to_string(format.height) + " F" +
         std::to_string(rateNumerator) + ":" + std::to_string(rateDenominator) + " Ip A1:1 C" + chroma + "\n";
}

std::string describeFormat(const FrameFormat& format) {
  const char* chroma = format.chroma == ChromaFormat::Yuv400   ? "4:0:0"
                       : format.chroma == ChromaFormat::Yuv444 ? "4:4:4"
                                                               : "4:2:0";
  return std::to_string(format.width) + "x" + std::to_string(format.height) + " " + chroma + " " +
         std::to_string(format.bitDepth) + "-bit";
}

std::string wholeFrameSizes(uint64_t fileBytes, const FrameFormat& format, int count) {
  if (fileBytes == 0) return "";
  const bool even = format.chroma == ChromaFormat::Yuv420;
  auto frames = [&](int w, int h) -> uint64_t {
    FrameFormat f = format;
    f.width = w;
    f.height = h;
    const uint64_t bytes = f.frameBytes();
    return bytes > 0 && fileBytes % bytes == 0 ? fileBytes / bytes : 0;
  };
  auto plural = [](uint64_t n) { return std::to_string(n) + (n == 1 ? " frame" : " frames"); };
  std::vector<std::string> items;
  // One dimension as configured, the other searched from half to twice its value, nearest first.
  for (int dimension = 0; dimension < 2; ++dimension) {
    const int configured = dimension == 0 ? format.width : format.height;
    std::vector<std::pair<int, uint64_t>> found;
    for (int v = std::max(1, configured / 2); v <= 2 * configured && v <= (1 << 16); ++v) {
      if (v == configured || (even && v % 2)) continue;
      const uint64_t n = dimension == 0 ? frames(v, format.height) : frames(format.width, v);
      if (n > 0) found.emplace_back(v, n);
    }
    std::stable_sort(found.begin(), found.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.first - configured) < std::abs(b.first - configured);
    });
    for (size_t i = 0; i < found.size() && int(i) < count; ++i)
      items.push_back(std::string(dimension == 0 ? "width " : "height ") + std::to_string(found[i].first) + " (" +
                      plural(found[i].second) + ")");
  }
  // The same size with another chroma format or sample size (one byte: 8-bit; two: 9- to 16-bit).
  for (ChromaFormat chroma : {ChromaFormat::Yuv420, ChromaFormat::Yuv400, ChromaFormat::Yuv444})
    for (int bitDepth : {8, 16}) {
      FrameFormat f = format;
      f.chroma = chroma;
      f.bitDepth = bitDepth;
      if (chroma == format.chroma && f.bytesPerSample() == format.bytesPerSample()) continue;
      if (fileBytes % f.frameBytes() != 0) continue;
      std::string item = chroma == format.chroma ? "" : std::string(chromaFormatName(chroma)) + " ";
      item += bitDepth == 8 ? "8-bit" : "9- to 16-bit";
      items.push_back(item + " samples (" + plural(fileBytes / f.frameBytes()) + ")");
    }
  static const int kCommon[][2] = {{3840, 2160}, {2048, 1088}, {1920, 1088}, {1920, 1080}, {1280, 720},
                                   {1024, 768},  {720, 576},   {640, 480},   {352, 288}};
  for (const auto& size : kCommon) {
    if (size[0] == format.width || size[1] == format.height) continue;  // the searches above cover these
    if (const uint64_t n = frames(size[0], size[1]))
      items.push_back(std::to_string(size[0]) + "x" + std::to_string(size[1]) + " (" + plural(n) + ")");
  }
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

}  // namespace vs
