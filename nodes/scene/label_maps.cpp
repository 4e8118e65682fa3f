#include "nodes/scene/label_maps.hpp"

#include "base/hash.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {

cv::Vec3b label_colour(int id) {
  const uint64_t h = splitmix64(static_cast<uint64_t>(id));
  // Bright enough to read over a dark scene: each channel in [64, 255].
  return {static_cast<uchar>(64 + (h & 0xff) * 191 / 255),
          static_cast<uchar>(64 + ((h >> 8) & 0xff) * 191 / 255),
          static_cast<uchar>(64 + ((h >> 16) & 0xff) * 191 / 255)};
}

void write_label_map_files(const LabelMapSet& maps, const Capture* rgb,
                           const std::filesystem::path& dir) {
  for (const LabelMap& m : maps.views) {
    write_label_png16(dir / (m.view + "_labels.png"), m.labels);
    if (!rgb) continue;
    const int v = rgb->find_view(m.view);
    if (v < 0 || !rgb->views[v].rgb.present()) continue;
    cv::Mat3b image = rgb->views[v].rgb.load();
    if (image.size() != m.labels.size()) continue;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const int id = m.labels(y, x);
        if (id == 0) continue;
        const cv::Vec3b c = label_colour(id);
        cv::Vec3b& p = image(y, x);
        for (int k = 0; k < 3; ++k) p[k] = static_cast<uchar>((p[k] + c[k]) / 2);
      }
    write_rgb_png(dir / (m.view + "_overlay.png"), image);
  }
}

}  // namespace gslift
