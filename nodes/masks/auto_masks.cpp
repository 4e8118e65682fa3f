#include "nodes/masks/auto_masks.hpp"

#include <tbb/parallel_for.h>
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/segmentation.hpp>

#include "base/errors.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/masks/label_segments.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {

std::vector<Mask> auto_masks(const cv::Mat& rgb, const AutoMaskOptions& o) {
  auto_mask_param_table().validate(o, "masks.auto");
  std::vector<Mask> out;
  const double scale_factor = rgb.cols / 640.0;
  for (size_t g = 0; g < o.scales.size(); ++g) {
    auto seg = cv::ximgproc::segmentation::createGraphSegmentation(
        o.sigma, static_cast<float>(o.scales[g] * scale_factor), o.keep.min_area);
    cv::Mat labels;
    seg->processImage(rgb, labels);
    append_label_segments(labels, static_cast<int>(g), o.keep, out);
  }
  return out;
}

MaskSet auto_mask_set(const Capture& capture, const AutoMaskOptions& o) {
  std::vector<int> views;
  for (int v : capture.views_named(o.keep.views))
    if (capture.views[v].rgb.present()) views.push_back(v);
  MaskSet set;
  set.views.resize(views.size());
  tbb::parallel_for(size_t(0), views.size(), [&](size_t i) {
    const View& view = capture.views[views[i]];
    set.views[i].view = view.name;
    set.views[i].masks = auto_masks(view.rgb.load(), o);
  });
  return set;
}

MaskSet ground_truth_masks(const Capture& capture, ViewSet which) {
  MaskSet set;
  for (int v : capture.views_named(which)) {
    const View& view = capture.views[v];
    if (!view.gt_instance.present()) continue;
    set.views.push_back({view.name, masks_from_instance_map(view.gt_instance.load())});
  }
  return set;
}

namespace {

// The stem as a number when it is all digits, else -1.
long long stem_number(const std::string& stem) {
  if (stem.empty() || stem.size() > 18 || stem.find_first_not_of("0123456789") != std::string::npos)
    return -1;
  return std::stoll(stem);
}

}  // namespace

const EnumNames<MaskChannel>& mask_channel_names() {
  static const EnumNames<MaskChannel> names = {{MaskChannel::Gray, "gray"},
                                               {MaskChannel::Alpha, "alpha"}};
  return names;
}

MaskSet mask_folder(const Capture& capture, const std::filesystem::path& folder, ViewSet which,
                    const std::string& label, MaskChannel channel) {
  if (!std::filesystem::is_directory(folder))
    throw InputError("masks.folder: no folder " + folder.string());
  std::map<std::string, std::filesystem::path> by_stem;
  std::map<long long, std::filesystem::path> by_number;
  for (const auto& e : std::filesystem::directory_iterator(folder)) {
    if (!e.is_regular_file()) continue;
    const std::string stem = e.path().stem().string();
    by_stem[stem] = e.path();
    if (stem_number(stem) >= 0) by_number[stem_number(stem)] = e.path();
  }
  MaskSet set;
  for (int v : capture.views_named(which)) {
    const View& view = capture.views[v];
    auto it = by_stem.find(view.name);
    std::filesystem::path file;
    if (it != by_stem.end()) {
      file = it->second;
    } else if (stem_number(view.name) >= 0 && by_number.count(stem_number(view.name))) {
      file = by_number[stem_number(view.name)];
    } else {
      continue;
    }
    cv::Mat m =
        channel == MaskChannel::Alpha ? read_alpha(file) : read_image(file, cv::IMREAD_GRAYSCALE);
    if (m.empty()) throw InputError("masks.folder: " + file.string() + " has no alpha channel");
    const cv::Size size(view.camera.width, view.camera.height);
    if (m.size() != size) cv::resize(m, m, size, 0, 0, cv::INTER_AREA);
    Mask mask;
    mask.pixels = m > 127;
    mask.label = label;
    set.views.push_back({view.name, {mask}});
  }
  return set;
}

const ParamTable<AutoMaskOptions>& auto_mask_param_table() {
  using O = AutoMaskOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("scales", &O::scales,
               "graph-segmentation scale k per granularity, coarse to fine (640-px-wide image)",
               1e-3, 1e7)
          .add("sigma", &O::sigma, "Gaussian smoothing before segmenting", 0, 100)
          .nest(&O::keep, segment_keep_param_table());
  return table;
}

}  // namespace gslift
