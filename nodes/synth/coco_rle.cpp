#include "nodes/synth/coco_rle.hpp"

#include <cstdint>
#include <vector>

namespace gslift::synth {

std::string coco_rle_counts(const cv::Mat1b& mask) {
  // Runs in column-major (Fortran) order, alternating 0-runs and 1-runs, starting with zeros.
  std::vector<int64_t> runs;
  bool current = false;
  int64_t length = 0;
  for (int x = 0; x < mask.cols; ++x) {
    for (int y = 0; y < mask.rows; ++y) {
      const bool inside = mask(y, x) != 0;
      if (inside != current) {
        runs.push_back(length);
        length = 0;
        current = inside;
      }
      ++length;
    }
  }
  runs.push_back(length);
  // pycocotools rleToString: each count (delta-coded against the count two back, from the
  // third on) as little-endian 5-bit groups with a continuation bit, offset by 48 into ASCII.
  std::string out;
  for (size_t i = 0; i < runs.size(); ++i) {
    int64_t x = runs[i];
    if (i > 2) x -= runs[i - 2];
    bool more = true;
    while (more) {
      int64_t c = x & 0x1f;
      x >>= 5;  // arithmetic shift: negative deltas end at -1
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      out.push_back(static_cast<char>(c + 48));
    }
  }
  return out;
}

nlohmann::json coco_rle(const cv::Mat1b& mask) {
  return {{"size", {mask.rows, mask.cols}}, {"counts", coco_rle_counts(mask)}};
}

}  // namespace gslift::synth
