#include "nodes/features/labelled_views.hpp"

#include "base/errors.hpp"

namespace gslift {

size_t LabelledViews::bytes() const {
  size_t b = 0;
  for (const auto& r : rows) b += r.bytes();
  return b;
}

LabelledViews labelled_training_views(const Capture& capture, const LabelMapSet& maps,
                                      const std::string& node) {
  LabelledViews out;
  for (size_t k = 0; k < maps.views.size(); ++k) {
    const LabelMap& m = maps.views[k];
    const int v = capture.find_view(m.view);
    if (v < 0)
      throw InputError(node + ": label map of view '" + m.view + "' is not in capture '" +
                       capture.name + "'");
    const View& view = capture.views[v];
    if (m.labels.cols != view.camera.width || m.labels.rows != view.camera.height)
      throw InputError(node + ": label map of view '" + m.view + "' is " +
                       std::to_string(m.labels.cols) + "x" + std::to_string(m.labels.rows) +
                       ", the view " + std::to_string(view.camera.width) + "x" +
                       std::to_string(view.camera.height));
    if (view.held_out) continue;
    out.capture_views.push_back(v);
    out.label_views.push_back(static_cast<int>(k));
    out.labels.push_back(m.labels.isContinuous() ? m.labels : m.labels.clone());
  }
  if (out.labels.empty())
    throw InputError(node + ": no training view of capture '" + capture.name + "' has a label map");
  return out;
}

LabelledViews render_labelled_views(const GaussianModel& model, const Capture& capture,
                                    const LabelMapSet& maps, double min_weight,
                                    const std::string& node) {
  LabelledViews out = labelled_training_views(capture, maps, node);
  for (const int v : out.capture_views) {
    const View& view = capture.views[v];
    out.rows.push_back(
        render_pixel_rows(model, view.camera, view.pose, static_cast<float>(min_weight)));
  }
  return out;
}

void sample_uniform_pixels(int n, size_t total, RandomStream& rng, std::vector<uint32_t>& pixels) {
  for (int k = 0; k < n; ++k) pixels.push_back(static_cast<uint32_t>(rng.below(total)));
}

}  // namespace gslift
