#include "nodes/scene/image_header.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>

#include "base/errors.hpp"
#include "nodes/scene/camera.hpp"

namespace gslift {
namespace {

// Random access to a file's bytes through a 4 KB window, so that a walk over neighbouring bytes
// (JPEG fill bytes and segments, a TIFF directory) reads the file once per window, not once per
// byte; a read past the end is an InputError "<file>: <format> header is cut short".
class HeaderBytes {
 public:
  explicit HeaderBytes(const std::filesystem::path& path)
      : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path.string() + ": cannot open image");
  }

  void set_format(const char* format) { format_ = format; }

  // Whether the file holds `bytes` at `offset` (false, not an error, when it is shorter).
  bool holds(std::uint64_t offset, std::initializer_list<int> bytes) {
    std::uint64_t i = offset;
    for (int b : bytes) {
      const auto got = try_byte(i++);
      if (!got || *got != static_cast<unsigned>(b)) return false;
    }
    return true;
  }

  unsigned byte(std::uint64_t offset) {
    if (const auto b = try_byte(offset)) return *b;
    throw InputError(path_.string() + ": " + format_ + " header is cut short");
  }

  // An unsigned integer of `size` bytes at `offset`, big- or little-endian.
  std::uint64_t uint(std::uint64_t offset, int size, bool big_endian) {
    std::uint64_t v = 0;
    for (int i = 0; i < size; ++i) {
      const std::uint64_t b = byte(offset + i);
      v |= big_endian ? b << (8 * (size - 1 - i)) : b << (8 * i);
    }
    return v;
  }

  [[noreturn]] void no_size(const std::string& why) {
    throw InputError(path_.string() + ": " + format_ + " header holds no image size (" + why + ")");
  }

 private:
  std::optional<unsigned> try_byte(std::uint64_t offset) {
    if (offset < window_start_ || offset >= window_start_ + window_.size()) {
      window_.resize(4096);
      in_.clear();
      in_.seekg(static_cast<std::streamoff>(offset));
      in_.read(window_.data(), static_cast<std::streamsize>(window_.size()));
      window_.resize(static_cast<size_t>(in_.gcount()));  // short at the end of the file
      window_start_ = offset;
      if (window_.empty()) return std::nullopt;
    }
    return static_cast<unsigned char>(window_[offset - window_start_]);
  }

  std::filesystem::path path_;
  std::ifstream in_;
  std::string window_;  // the bytes at window_start_
  std::uint64_t window_start_ = 0;
  std::string format_ = "image";
};

// PNG: the IHDR chunk comes first (PNG spec 11.2.2): width and height at bytes 16 and 20.
ImageHeader png(HeaderBytes& f) {
  if (!f.holds(12, {'I', 'H', 'D', 'R'})) f.no_size("the first chunk is not IHDR");
  return {"PNG", static_cast<long long>(f.uint(16, 4, true)),
          static_cast<long long>(f.uint(20, 4, true)), 8};
}

// JPEG: the segments before the first scan, walked by their lengths up to a start-of-frame marker
// (ITU T.81 B.2.2: precision, then height and width, 16 bits each).
ImageHeader jpeg(HeaderBytes& f) {
  std::uint64_t at = 2;
  while (true) {
    if (f.byte(at) != 0xff) f.no_size("a segment does not start with a marker");
    while (f.byte(at) == 0xff) ++at;  // fill bytes
    const unsigned marker = f.byte(at++);
    const bool start_of_frame =
        marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (start_of_frame)
      return {"JPEG", static_cast<long long>(f.uint(at + 5, 2, true)),
              static_cast<long long>(f.uint(at + 3, 2, true)), 4};
    if (marker == 0xda || marker == 0xd9) f.no_size("no frame before the first scan");
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) continue;  // no length field
    const std::uint64_t length = f.uint(at, 2, true);
    if (length < 2) f.no_size("a segment length below 2");
    at += length;
  }
}

// TIFF: ImageWidth (256), ImageLength (257), BitsPerSample (258) and SamplesPerPixel (277) in the
// first image file directory, the one OpenCV decodes (TIFF 6.0, section 2). Each is a SHORT or
// LONG; BitsPerSample has one value per sample, the first of which is taken (OpenCV reads one).
ImageHeader tiff(HeaderBytes& f) {
  const bool big = f.byte(0) == 'M';
  const std::uint64_t ifd = f.uint(4, 4, big);
  const std::uint64_t entries = f.uint(ifd, 2, big);
  long long width = -1, height = -1, bits = 1, samples = 1;  // the spec's defaults for the last two
  for (std::uint64_t i = 0; i < entries; ++i) {
    const std::uint64_t entry = ifd + 2 + 12 * i;
    const auto tag = f.uint(entry, 2, big);
    if (tag != 256 && tag != 257 && tag != 258 && tag != 277) continue;
    const auto type = f.uint(entry + 2, 2, big);
    if (type != 3 && type != 4) f.no_size("tag " + std::to_string(tag) + " is not a SHORT or LONG");
    const int size = type == 3 ? 2 : 4;
    // Values that do not fit in the entry's 4 bytes are stored at the offset it holds instead.
    const std::uint64_t at =
        f.uint(entry + 4, 4, big) * size > 4 ? f.uint(entry + 8, 4, big) : entry + 8;
    const auto value = static_cast<long long>(f.uint(at, size, big));
    (tag == 256 ? width : tag == 257 ? height : tag == 258 ? bits : samples) = value;
  }
  if (width < 0 || height < 0) f.no_size("no ImageWidth or ImageLength in the first directory");
  return {"TIFF", width, height, std::max(samples, 1LL) * std::max((bits + 7) / 8, 1LL)};
}

// BMP: the info header after the 14-byte file header; OS/2's 12-byte core header has 16-bit
// sizes, every later one signed 32-bit sizes (a negative height is a top-down image).
ImageHeader bmp(HeaderBytes& f) {
  if (f.uint(14, 4, false) == 12)
    return {"BMP", static_cast<long long>(f.uint(18, 2, false)),
            static_cast<long long>(f.uint(20, 2, false)), 4};
  const auto width = static_cast<std::int32_t>(f.uint(18, 4, false));
  const auto height = static_cast<std::int32_t>(f.uint(22, 4, false));
  return {"BMP", static_cast<long long>(width), std::llabs(static_cast<long long>(height)), 4};
}

// WebP: the first chunk after "RIFF....WEBP" is the lossy frame (VP8, RFC 6386 9.1: 14-bit sizes
// after the start code), the lossless one (VP8L: 14-bit sizes minus one after the signature byte)
// or the extended header (VP8X: 24-bit canvas sizes minus one).
ImageHeader webp(HeaderBytes& f) {
  if (f.holds(12, {'V', 'P', '8', ' '})) {
    if (!f.holds(23, {0x9d, 0x01, 0x2a})) f.no_size("no VP8 key frame start code");
    return {"WebP", static_cast<long long>(f.uint(26, 2, false) & 0x3fff),
            static_cast<long long>(f.uint(28, 2, false) & 0x3fff), 4};
  }
  if (f.holds(12, {'V', 'P', '8', 'L'})) {
    if (f.byte(20) != 0x2f) f.no_size("no VP8L signature");
    const std::uint64_t bits = f.uint(21, 4, false);
    return {"WebP", static_cast<long long>(bits & 0x3fff) + 1,
            static_cast<long long>((bits >> 14) & 0x3fff) + 1, 4};
  }
  if (f.holds(12, {'V', 'P', '8', 'X'}))
    return {"WebP", static_cast<long long>(f.uint(24, 3, false)) + 1,
            static_cast<long long>(f.uint(27, 3, false)) + 1, 4};
  f.no_size("the first chunk is not VP8, VP8L or VP8X");
}

// OpenEXR: the header's attributes (name, type name, byte size, value) up to an empty name; the
// image is the "dataWindow" box2i, inclusive (xMin, yMin, xMax, yMax).
ImageHeader openexr(HeaderBytes& f) {
  std::uint64_t at = 8;  // after the magic number and the version field
  const auto read_string = [&] {
    std::string s;
    for (unsigned c; (c = f.byte(at++)) != 0;) {
      if (s.size() == 255) f.no_size("an attribute name longer than 255 bytes");
      s += static_cast<char>(c);
    }
    return s;
  };
  while (true) {
    const std::string name = read_string();
    if (name.empty()) f.no_size("no dataWindow attribute");
    const std::string type = read_string();
    const std::uint64_t size = f.uint(at, 4, false);
    at += 4;
    if (name == "dataWindow") {
      if (type != "box2i" || size != 16) f.no_size("dataWindow is not a box2i");
      std::array<long long, 4> box;
      for (int i = 0; i < 4; ++i) box[i] = static_cast<std::int32_t>(f.uint(at + 4 * i, 4, false));
      return {"OpenEXR", box[2] - box[0] + 1, box[3] - box[1] + 1, 16};
    }
    at += size;
  }
}

}  // namespace

ImageHeader read_image_header(const std::filesystem::path& path) {
  HeaderBytes f(path);
  const struct {
    const char* format;
    bool matches;
    ImageHeader (*read)(HeaderBytes&);
  } formats[] = {
      {"PNG", f.holds(0, {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}), png},
      {"JPEG", f.holds(0, {0xff, 0xd8, 0xff}), jpeg},
      {"TIFF", f.holds(0, {'I', 'I', 42, 0}) || f.holds(0, {'M', 'M', 0, 42}), tiff},
      {"BMP", f.holds(0, {'B', 'M'}), bmp},
      {"WebP", f.holds(0, {'R', 'I', 'F', 'F'}) && f.holds(8, {'W', 'E', 'B', 'P'}), webp},
      {"OpenEXR", f.holds(0, {0x76, 0x2f, 0x31, 0x01}), openexr},
  };
  for (const auto& format : formats)
    if (format.matches) {
      f.set_format(format.format);
      return format.read(f);
    }
  throw InputError(path.string() + ": not a PNG, JPEG, TIFF, BMP, WebP or OpenEXR image");
}

void check_image_header(const ImageHeader& header, const std::string& where) {
  check_image_size(header.width, header.height, where);
  // width * height is within kMaxImagePixels here, so nothing below overflows.
  const long long bytes = std::max(header.bytes_per_pixel, 1LL);
  if (bytes > kMaxDecodedImageBytes || header.width * header.height > kMaxDecodedImageBytes / bytes)
    throw InputError(where + ": a " + std::to_string(header.width) + " x " +
                     std::to_string(header.height) + " image of " +
                     std::to_string(header.bytes_per_pixel) +
                     " bytes a pixel is over gslift's limit of " +
                     std::to_string(kMaxDecodedImageBytes) + " bytes (docs/security.md)");
}

}  // namespace gslift
