#include "nodes/scene/label_maps.hpp"

#include <algorithm>
#include <map>

#include "base/hash.hpp"
#include "nodes/scene/caption_strip.hpp"
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

cv::Mat3b label_image(const cv::Mat1i& ids) {
  cv::Mat3b image(ids.size(), cv::Vec3b(0, 0, 0));
  for (int y = 0; y < ids.rows; ++y)
    for (int x = 0; x < ids.cols; ++x)
      if (ids(y, x) > 0) image(y, x) = label_colour(ids(y, x));
  return image;
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
    std::map<int, int> area;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) {
        const int id = m.labels(y, x);
        if (id == 0) continue;
        ++area[id];
        const cv::Vec3b c = label_colour(id);
        cv::Vec3b& p = image(y, x);
        for (int k = 0; k < 3; ++k) p[k] = static_cast<uchar>((p[k] + c[k]) / 2);
      }
    // The legend names the largest labels; a view of many speckle labels would fill a page.
    constexpr size_t kLegendIds = 16;
    std::vector<std::pair<int, int>> by_area;
    for (const auto& [id, pixels] : area) by_area.push_back({-pixels, id});
    std::sort(by_area.begin(), by_area.end());
    std::vector<LegendEntry> legend;
    for (size_t k = 0; k < by_area.size() && k < kLegendIds; ++k)
      legend.push_back(
          {"id " + std::to_string(by_area[k].second), label_colour(by_area[k].second)});
    const std::string more =
        by_area.size() > kLegendIds
            ? " (" + std::to_string(by_area.size() - kLegendIds) + " smaller labels not listed)"
            : std::string();
    write_rgb_png(dir / (m.view + "_overlay.png"),
                  with_caption(image,
                               m.view +
                                   ": instance labels over the view, a colour per id; "
                                   "uncoloured: unlabelled" +
                                   more,
                               legend));
  }
}

}  // namespace gslift
