#include "nodes/ingest/coco_rle.hpp"

#include <algorithm>

#include "base/errors.hpp"
#include "nodes/scene/camera.hpp"

namespace gslift {

std::vector<uint32_t> rle_encode(const cv::Mat1b& mask) {
  std::vector<uint32_t> counts;
  uint8_t value = 0;  // runs start with background
  uint32_t run = 0;
  for (int x = 0; x < mask.cols; ++x)
    for (int y = 0; y < mask.rows; ++y) {
      const uint8_t v = mask(y, x) ? 1 : 0;
      if (v != value) {
        counts.push_back(run);
        run = 0;
        value = v;
      }
      ++run;
    }
  counts.push_back(run);
  return counts;
}

cv::Mat1b rle_decode(const std::vector<uint32_t>& counts, int height, int width,
                     const std::string& where) {
  // A record's size is checked before anything is allocated: [0, 0] has no pixels to decode into,
  // and a size over kMaxImagePixels (camera.hpp) would cost gigabytes for a few bytes of counts.
  check_image_size(height, width, where + " (RLE size [height, width])");
  uint64_t total = 0;
  for (uint32_t c : counts) total += c;
  if (total != static_cast<uint64_t>(height) * width)
    throw InputError(where + ": RLE counts sum to " + std::to_string(total) + ", but the mask is " +
                     std::to_string(height) + " x " + std::to_string(width) + " = " +
                     std::to_string(static_cast<int64_t>(height) * width) + " pixels");
  // Fill the transpose row by row (= the mask column by column), then transpose back.
  cv::Mat1b columns(width, height, uchar(0));
  uchar* p = columns.ptr<uchar>();
  uchar value = 0;
  for (uint32_t c : counts) {
    std::fill(p, p + c, value);
    p += c;
    value = value ? 0 : 255;
  }
  return columns.t();
}

std::string rle_counts_to_string(const std::vector<uint32_t>& counts) {
  std::string s;
  for (size_t i = 0; i < counts.size(); ++i) {
    int64_t x = counts[i];
    if (i > 2) x -= counts[i - 2];
    bool more = true;
    while (more) {
      char c = static_cast<char>(x & 0x1f);
      x >>= 5;  // arithmetic shift: negative deltas end in a run of 1 bits
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      s.push_back(static_cast<char>(c + 48));
    }
  }
  return s;
}

std::vector<uint32_t> rle_counts_from_string(const std::string& s, const std::string& where) {
  std::vector<int64_t> counts;
  size_t p = 0;
  while (p < s.size()) {
    int64_t x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      if (p >= s.size()) throw InputError(where + ": RLE string ends inside a count");
      const int c = s[p] - 48;
      if (c < 0 || c > 63 || k > 6)
        throw InputError(where + ": invalid RLE string character '" + std::string(1, s[p]) +
                         "' at " + std::to_string(p));
      x |= static_cast<int64_t>(c & 0x1f) << (5 * k);
      more = c & 0x20;
      ++p;
      ++k;
      if (!more && (c & 0x10)) x -= int64_t(1) << (5 * k);  // sign extension
    }
    if (counts.size() > 2) x += counts[counts.size() - 2];
    if (x < 0 || x > UINT32_MAX)
      throw InputError(where + ": RLE string decodes to an invalid count " + std::to_string(x));
    counts.push_back(x);
  }
  return {counts.begin(), counts.end()};
}

cv::Mat1b rle_decode_json(const nlohmann::json& rle, const std::string& where) {
  if (!rle.is_object() || !rle.contains("size") || !rle.contains("counts"))
    throw InputError(where + ": expected a COCO RLE {\"size\": [h, w], \"counts\": ...}");
  const auto& size = rle["size"];
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
      !size[1].is_number_integer())
    throw InputError(where + ": RLE size must be [height, width]");
  // As int64: get<int> of 1e10 would wrap.
  const int64_t h64 = size[0].get<int64_t>(), w64 = size[1].get<int64_t>();
  check_image_size(h64, w64, where + " (RLE size [height, width])");
  const int h = static_cast<int>(h64), w = static_cast<int>(w64);
  const auto& counts = rle["counts"];
  if (counts.is_string())
    return rle_decode(rle_counts_from_string(counts.get<std::string>(), where), h, w, where);
  if (!counts.is_array()) throw InputError(where + ": RLE counts must be a string or a list");
  std::vector<uint32_t> c;
  for (const auto& v : counts) {
    if (!v.is_number_integer() || v.get<int64_t>() < 0 || v.get<int64_t>() > UINT32_MAX)
      throw InputError(where + ": RLE counts must be non-negative integers");
    c.push_back(static_cast<uint32_t>(v.get<int64_t>()));
  }
  return rle_decode(c, h, w, where);
}

}  // namespace gslift
