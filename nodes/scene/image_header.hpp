// What an image file's header declares, read from its bytes before any decoder runs (issue 16,
// docs/security.md). cv::imread allocates whatever size a header claims, up to OpenCV's own limit
// of 2^30 pixels: a few hundred bytes of TIFF, JPEG or BMP claiming 30000 x 30000 cost gigabytes
// before the decode fails (found by the mask_png and depth_image fuzzers in CI). read_image
// checks this size against kMaxImagePixels first.
#pragma once

#include <filesystem>
#include <string>

namespace gslift {

struct ImageHeader {
  std::string format;  // "PNG", "JPEG", "TIFF", "BMP", "WebP" or "OpenEXR"
  long long width = 0;
  long long height = 0;
  // The most bytes a pixel of the decoded image can take: fixed by the format (16-bit RGBA PNG: 8,
  // four float channels of OpenEXR: 16), or from the header for TIFF, whose samples may be 64-bit
  // and many (a 8192 x 8192 TIFF of four doubles is 2 GB).
  long long bytes_per_pixel = 0;
};

// The most bytes one decoded image may take: 2^30, four float channels at kMaxImagePixels.
constexpr long long kMaxDecodedImageBytes = 1LL << 30;

// The format, from the file's first bytes (cv::imread picks its decoder by sniffing the content,
// not the name), and the size its header declares. Throws InputError naming the file when it
// starts like none of the formats gslift reads, or when its header is cut short or holds no size
// (no decoder could read such a file either). The size is returned as declared, unchecked.
ImageHeader read_image_header(const std::filesystem::path& path);

// Throws InputError "<where>: ..." unless the header's size passes check_image_size (camera.hpp)
// and the decoded image stays within kMaxDecodedImageBytes.
void check_image_header(const ImageHeader& header, const std::string& where);

}  // namespace gslift
