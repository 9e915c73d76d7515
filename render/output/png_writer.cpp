#include "render/output/png_writer.h"

#include <libdeflate.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

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

namespace {

void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (const int shift : {24, 16, 8, 0}) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

// A PNG chunk: length, type, data, and the CRC-32 of type and data (PNG spec, section 5.3).
void appendChunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::uint8_t* data,
                 std::size_t size) {
  put32(out, static_cast<std::uint32_t>(size));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  put32(out, libdeflate_crc32(0, out.data() + start, size + 4));
}

}  // namespace

std::vector<std::uint8_t> encodePng(const Image& image, PngCompression compression,
                                    const std::string& where) {
  const bool alpha = !image.alpha.empty();
  const std::size_t channels = alpha ? 4 : 3;
  const std::size_t w = static_cast<std::size_t>(image.width);
  const std::size_t rowBytes = 1 + w * channels;
  // The filtered image data (PNG spec, section 7.3): each row's filter type (0: none), then its
  // pixels, RGB or RGBA.
  std::vector<std::uint8_t> rows(rowBytes * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    std::uint8_t* row = rows.data() + rowBytes * static_cast<std::size_t>(y);
    row[0] = 0;
    const std::uint8_t* rgb = image.pixel(0, y);
    if (!alpha) {
      std::memcpy(row + 1, rgb, w * 3);
      continue;
    }
    const std::uint8_t* a = image.alpha.data() + w * static_cast<std::size_t>(y);
    for (std::size_t x = 0; x < w; ++x) {
      std::memcpy(row + 1 + 4 * x, rgb + 3 * x, 3);
      row[1 + 4 * x + 3] = a[x];
    }
  }
  libdeflate_compressor* compressor =
      libdeflate_alloc_compressor(compression == PngCompression::fast ? 1 : 6);
  if (compressor == nullptr) throw InputError(where, "cannot write PNG: out of memory");
  std::vector<std::uint8_t> zlib(libdeflate_zlib_compress_bound(compressor, rows.size()));
  const std::size_t packed =
      libdeflate_zlib_compress(compressor, rows.data(), rows.size(), zlib.data(), zlib.size());
  libdeflate_free_compressor(compressor);
  VF_ASSERT(packed > 0);  // the bound always suffices

  static constexpr std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> out(kSignature, kSignature + 8);
  out.reserve(packed + 64);
  std::vector<std::uint8_t> header;
  put32(header, static_cast<std::uint32_t>(image.width));
  put32(header, static_cast<std::uint32_t>(image.height));
  // Bit depth 8; colour type 2 (RGB) or 6 (RGBA); deflate; adaptive filtering (type 0 rows
  // only); no interlace.
  header.insert(header.end(), {8, static_cast<std::uint8_t>(alpha ? 6 : 2), 0, 0, 0});
  appendChunk(out, "IHDR", header.data(), header.size());
  const std::uint8_t perceptual = 0;  // sRGB rendering intent, as libpng's writer tags it
  appendChunk(out, "sRGB", &perceptual, 1);
  appendChunk(out, "IDAT", zlib.data(), packed);
  appendChunk(out, "IEND", nullptr, 0);
  return out;
}

namespace {

// Writes encoded bytes into `out` and renames it into place.
void commitBytes(OutputFile& out, const std::vector<std::uint8_t>& bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), out.stream()) != bytes.size())
    throw InputError(out.path(), std::string("cannot write PNG: ") + std::strerror(errno));
  out.commit();
}

}  // namespace

void writePng(const std::string& path, const Image& image, const OutputRules& rules,
              PngCompression compression) {
  // The file is checked and created first: an unwritable destination is reported before the
  // work of compressing.
  OutputFile out(path, rules);
  commitBytes(out, encodePng(image, compression, path));
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

// --- The sequence writer ----------------------------------------------------------------

// Frames in order, each compressed by whichever worker takes it; the caller's thread writes
// the front frames once they are compressed.
struct PngSequenceWriter::Impl {
  struct Frame {
    int index = 0;
    Image image;
    std::vector<std::uint8_t> bytes;
    std::exception_ptr failure;
    bool taken = false;  // a worker has it
    bool done = false;   // compressed (or failed)
  };
  std::string pattern;
  OutputRules rules;
  std::vector<std::thread> workers;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::unique_ptr<Frame>> frames;  // accepted, not yet written, in frame order
  bool closing = false;                       // workers stop once nothing is left to take
  std::exception_ptr failure;                 // the first write that failed: every later call
  int accepted = 0;

  std::size_t depth() const { return 2 * workers.size(); }
  void compressLoop();
  // Writes the compressed frames at the front; with `wait`, until none is left.
  void writeReady(bool wait);
  void stopWorkers();
};

void PngSequenceWriter::Impl::compressLoop() {
  for (;;) {
    Frame* frame = nullptr;
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] {
        if (closing) return true;
        for (const auto& f : frames)
          if (!f->taken) return true;
        return false;
      });
      for (const auto& f : frames) {
        if (!f->taken) {
          frame = f.get();
          frame->taken = true;
          break;
        }
      }
      if (frame == nullptr) return;  // closing, nothing left to take
    }
    try {
      frame->bytes =
          encodePng(frame->image, PngCompression::fast, expandFramePattern(pattern, frame->index));
    } catch (...) {
      frame->failure = std::current_exception();
    }
    {
      std::lock_guard lock(mutex);
      frame->image = Image();  // the pixels are no longer needed
      frame->done = true;
    }
    changed.notify_all();
  }
}

void PngSequenceWriter::Impl::writeReady(bool wait) {
  if (failure) std::rethrow_exception(failure);
  for (;;) {
    std::unique_ptr<Frame> front;
    {
      std::unique_lock lock(mutex);
      if (frames.empty()) return;
      if (wait) changed.wait(lock, [&] { return frames.front()->done; });
      if (!frames.front()->done) return;
      front = std::move(frames.front());
      frames.pop_front();
    }
    changed.notify_all();  // a place in the queue is free
    try {
      if (front->failure) std::rethrow_exception(front->failure);
      OutputFile out(expandFramePattern(pattern, front->index), rules);
      commitBytes(out, front->bytes);
    } catch (...) {
      failure = std::current_exception();
      throw;
    }
  }
}

void PngSequenceWriter::Impl::stopWorkers() {
  {
    std::lock_guard lock(mutex);
    closing = true;
    // Frames no worker has taken are dropped; those being compressed finish first.
    std::erase_if(frames, [](const std::unique_ptr<Frame>& f) { return !f->taken; });
  }
  changed.notify_all();
  for (std::thread& w : workers) w.join();
  workers.clear();
}

PngSequenceWriter::PngSequenceWriter(std::string pattern, OutputRules rules, int threads)
    : impl_(std::make_unique<Impl>()) {
  impl_->pattern = std::move(pattern);
  impl_->rules = std::move(rules);
  if (threads <= 0)
    threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, kMaxPngThreads);
  for (int i = 0; i < threads; ++i) impl_->workers.emplace_back([this] { impl_->compressLoop(); });
}

PngSequenceWriter::~PngSequenceWriter() { impl_->stopWorkers(); }

void PngSequenceWriter::write(int index, const Image& image) {
  Impl& w = *impl_;
  w.writeReady(false);
  {
    std::unique_lock lock(w.mutex);
    // Bounded: the drawing waits for compression rather than piling frames up in memory.
    while (w.frames.size() >= w.depth()) {
      if (w.frames.front()->done) {
        lock.unlock();
        w.writeReady(false);
        lock.lock();
        continue;
      }
      w.changed.wait(lock);
    }
    auto frame = std::make_unique<Impl::Frame>();
    frame->index = index;
    frame->image = image;
    w.frames.push_back(std::move(frame));
  }
  w.changed.notify_all();
  ++w.accepted;
}

void PngSequenceWriter::finish() { impl_->writeReady(true); }

int PngSequenceWriter::framesWritten() const { return impl_->accepted; }

std::string PngSequenceWriter::path() const { return impl_->pattern; }

int PngSequenceWriter::threads() const { return static_cast<int>(impl_->workers.size()); }

}  // namespace vf
