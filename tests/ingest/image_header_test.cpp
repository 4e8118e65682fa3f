#include "nodes/scene/image_header.hpp"

#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "base/errors.hpp"
#include "nodes/scene/image_io.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

fs::path write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string le(unsigned long long v, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}

std::string be(unsigned long long v, int n) {
  std::string s;
  for (int i = n - 1; i >= 0; --i) s += static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}

}  // namespace

TEST_CASE("read_image_header reads the size of every format OpenCV writes") {
  const auto dir = test::scratch_dir("image_header_formats");
  const cv::Mat image(6, 8, CV_8UC3, cv::Scalar(10, 20, 30));  // 8 wide, 6 high
  const std::pair<const char*, const char*> formats[] = {
      {".png", "PNG"}, {".jpg", "JPEG"}, {".tiff", "TIFF"}, {".bmp", "BMP"}, {".webp", "WebP"}};
  for (const auto& [ext, format] : formats) {
    INFO(ext);
    const fs::path file = dir / (std::string("a") + ext);
    REQUIRE(cv::imwrite(file.string(), image));
    const ImageHeader header = read_image_header(file);
    CHECK(header.format == format);
    CHECK(header.width == 8);
    CHECK(header.height == 6);
  }
  // Three 8-bit samples: BitsPerSample is stored outside its entry, at the offset it holds.
  CHECK(read_image_header(dir / "a.tiff").bytes_per_pixel == 3);
  // Lossless WebP (VP8L) and a float TIFF, as depth priors are stored.
  const fs::path lossless = dir / "lossless.webp";
  REQUIRE(cv::imwrite(lossless.string(), image, {cv::IMWRITE_WEBP_QUALITY, 101}));
  CHECK(read_image_header(lossless).width == 8);
  CHECK(read_image_header(lossless).height == 6);
  const fs::path depth = dir / "depth.tiff";
  write_depth_tiff(depth, cv::Mat(6, 8, CV_32FC1, cv::Scalar(1.5)));
  CHECK(read_image_header(depth).width == 8);
  CHECK(read_image_header(depth).height == 6);
  CHECK(read_image_header(depth).bytes_per_pixel == 4);
  if (cv::haveImageWriter((dir / "a.exr").string())) {
    REQUIRE(cv::imwrite((dir / "a.exr").string(), cv::Mat(6, 8, CV_32FC1, cv::Scalar(1.5))));
    const ImageHeader exr = read_image_header(dir / "a.exr");
    CHECK(exr.format == "OpenEXR");
    CHECK(exr.width == 8);
    CHECK(exr.height == 6);
  }
}

TEST_CASE("a header claiming a huge image is refused before OpenCV allocates for it", "[hostile]") {
  // Each file is a few dozen bytes that cv::imread would answer by allocating the claimed size
  // (up to OpenCV's own limit of 2^30 pixels) before the decode fails.
  const auto dir = test::scratch_dir("image_header_huge");
  const std::string tiff_entry_w = le(256, 2) + le(4, 2) + le(1, 4) + le(100000, 4);
  const std::string tiff_entry_h = le(257, 2) + le(3, 2) + le(1, 4) + le(50000, 2) + le(0, 2);
  const std::string exr_window = "dataWindow" + std::string(1, '\0') + "box2i" +
                                 std::string(1, '\0') + le(16, 4) + le(0, 4) + le(0, 4) +
                                 le(99999, 4) + le(49999, 4);
  const std::pair<std::string, std::string> files[] = {
      {"PNG", "\x89PNG\r\n\x1a\n" + be(13, 4) + "IHDR" + be(100000, 4) + be(50000, 4)},
      {"JPEG", "\xff\xd8\xff\xe0" + be(4, 2) + "ab" + "\xff\xc0" + be(11, 2) + "\x08" +
                   be(50000, 2) + be(100000 & 0xffff, 2)},
      {"TIFF", "II*" + std::string(1, '\0') + le(8, 4) + le(2, 2) + tiff_entry_w + tiff_entry_h},
      {"BMP", "BM" + std::string(12, '\0') + le(40, 4) + le(100000, 4) + le(-50000, 4)},
      {"WebP",
       "RIFF" + le(30, 4) + "WEBPVP8X" + le(10, 4) + le(0, 4) + le(99999, 3) + le(49999, 3)},
      {"OpenEXR", "\x76\x2f\x31\x01" + le(2, 4) + "channels" + std::string(1, '\0') + "chlist" +
                      std::string(1, '\0') + le(1, 4) + std::string(1, '\0') + exr_window},
  };
  for (const auto& [format, bytes] : files) {
    INFO(format);
    const fs::path file = write_bytes(dir / ("huge_" + format), bytes);
    const ImageHeader header = read_image_header(file);
    CHECK(header.format == format);
    CHECK(header.height == 50000);
    CHECK(header.width == (format == "JPEG" ? (100000 & 0xffff) : 100000));
    CHECK_THROWS_WITH(read_image(file), Contains(file.string() + " (" + format +
                                                 " header): image "
                                                 "size") &&
                                            Contains("is over gslift's limit"));
  }
}

TEST_CASE("a TIFF within the pixel limit whose samples would take over 1 GB is refused",
          "[hostile]") {
  // 8192 x 8192 is exactly kMaxImagePixels; four 64-bit samples make it 2 GB when decoded.
  const auto dir = test::scratch_dir("image_header_tiff_bytes");
  const auto entry = [](int tag, unsigned long long value) {
    return le(tag, 2) + le(4, 2) + le(1, 4) + le(value, 4);
  };
  const auto tiff = [&](int bits, int samples) {
    return "II*" + std::string(1, '\0') + le(8, 4) + le(4, 2) + entry(256, 8192) +
           entry(257, 8192) + entry(258, bits) + entry(277, samples);
  };
  const fs::path doubles = write_bytes(dir / "doubles.tiff", tiff(64, 4));
  CHECK(read_image_header(doubles).bytes_per_pixel == 32);
  CHECK_THROWS_WITH(read_image(doubles),
                    Contains("doubles.tiff (TIFF header): a 8192 x 8192 image of 32 bytes a pixel "
                             "is over gslift's limit of 1073741824 bytes"));
  // Four floats of the same size are within the limit (1 GB).
  const fs::path floats = write_bytes(dir / "floats.tiff", tiff(32, 4));
  CHECK(read_image_header(floats).bytes_per_pixel == 16);
  CHECK_NOTHROW(check_image_header(read_image_header(floats), "floats.tiff"));
}

TEST_CASE("a header cut short or without a size is refused naming the file and format",
          "[hostile]") {
  const auto dir = test::scratch_dir("image_header_broken");
  const std::pair<std::string, std::string> cut_short[] = {
      {"PNG", "\x89PNG\r\n\x1a\n" + be(13, 4) + "IHDR" + be(8, 4)},
      {"JPEG", "\xff\xd8\xff\xe0" + be(200, 2) + "ab"},           // a segment running past the end
      {"TIFF", "MM" + std::string(1, '\0') + "*" + be(4000, 4)},  // directory past the end
      {"BMP", "BM" + std::string(12, '\0') + le(40, 4) + le(8, 4)},
      {"OpenEXR", "\x76\x2f\x31\x01" + le(2, 4) + "dataWin"},
  };
  for (const auto& [format, bytes] : cut_short) {
    INFO(format);
    const fs::path file = write_bytes(dir / ("short_" + format), bytes);
    CHECK_THROWS_AS(read_image_header(file), InputError);
    CHECK_THROWS_WITH(read_image_header(file),
                      Contains(file.string() + ": " + format + " header is cut short"));
  }
  const std::pair<std::string, std::string> no_size[] = {
      {"PNG", "\x89PNG\r\n\x1a\n" + be(13, 4) + "IDAT" + be(8, 4) + be(6, 4)},
      {"JPEG", "\xff\xd8\xff\xda" + be(2, 2)},                       // a scan before any frame
      {"TIFF", "II*" + std::string(1, '\0') + le(8, 4) + le(0, 2)},  // an empty directory
      {"WebP", "RIFF" + le(30, 4) + "WEBPALPH" + le(10, 4) + std::string(10, '\0')},
      {"OpenEXR", "\x76\x2f\x31\x01" + le(2, 4) + std::string(1, '\0')},
  };
  for (const auto& [format, bytes] : no_size) {
    INFO(format);
    const fs::path file = write_bytes(dir / ("no_size_" + format), bytes);
    CHECK_THROWS_WITH(read_image(file),
                      Contains(file.string() + ": " + format + " header holds no image size"));
  }
  CHECK_THROWS_WITH(read_image_header(write_bytes(dir / "text.png", "not an image")),
                    Contains("text.png: not a PNG, JPEG, TIFF, BMP, WebP or OpenEXR image"));
}
