#include "render/output/png_writer.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "sim/core/error.h"

namespace vf {

std::string expandFramePattern(const std::string& pattern, int frame) {
  const std::size_t last = pattern.find_last_of('#');
  if (last == std::string::npos) return pattern;
  std::size_t first = last;
  while (first > 0 && pattern[first - 1] == '#') --first;
  const std::size_t width = last - first + 1;
  std::string number = std::to_string(frame < 0 ? -frame : frame);
  if (number.size() < width) number.insert(0, width - number.size(), '0');
  if (frame < 0) number.insert(0, 1, '-');
  return pattern.substr(0, first) + number + pattern.substr(last + 1);
}

void writePng(const std::string& path, const Image& image, const OutputRules& rules) {
  OutputFile out(path, rules);
  // libpng's simplified API: errors come back as a return value and a message instead of a
  // longjmp through C++ frames. It tags 8-bit non-linear data as sRGB.
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  const bool encoded = png_image_write_to_stdio(&png, out.stream(), 0, image.rgb.data(),
                                                image.width * 3, nullptr) != 0;
  const std::string pngMessage = png.message;
  png_image_free(&png);
  if (!encoded) throw InputError(path, "cannot write PNG: " + pngMessage);
  out.commit();
}

Image readPng(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) throw InputError(path, std::string("cannot read PNG: ") + std::strerror(errno));
  // The simplified API again (no longjmp); it converts every colour type and bit depth to the
  // format asked for, with sRGB encoding for 8-bit output.
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  Image image;
  bool ok = png_image_begin_read_from_stdio(&png, file) != 0;
  // A corrupt or hostile header must not become a multi-gigabyte allocation.
  constexpr png_uint_32 kMaxSide = 16384;
  const bool tooLarge = ok && (png.width > kMaxSide || png.height > kMaxSide);
  if (tooLarge) {
    ok = false;
    std::snprintf(png.message, sizeof png.message, "%ux%u pixels is larger than %ux%u",
                  static_cast<unsigned>(png.width), static_cast<unsigned>(png.height),
                  static_cast<unsigned>(kMaxSide), static_cast<unsigned>(kMaxSide));
  }
  if (ok) {
    png.format = PNG_FORMAT_RGB;
    image = Image(static_cast<int>(png.width), static_cast<int>(png.height));
    // With background null, alpha is composited onto the buffer's contents: black.
    ok = png_image_finish_read(&png, nullptr, image.rgb.data(), image.width * 3, nullptr) != 0;
  }
  const std::string pngMessage = png.message;
  png_image_free(&png);
  std::fclose(file);
  if (!ok) throw InputError(path, "cannot read PNG: " + pngMessage);
  return image;
}

void PngSequenceWriter::write(int index, const Image& image) {
  writePng(expandFramePattern(pattern_, index), image, rules_);
  ++frames_;
}

}  // namespace vf
