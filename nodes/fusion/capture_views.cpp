#include "nodes/fusion/capture_views.hpp"

#include <string>

#include "base/errors.hpp"

namespace gslift {

const View& capture_view(const Capture& capture, const SemanticView& sv, const char* stage) {
  const int v = capture.find_view(sv.view);
  if (v < 0)
    throw InputError(std::string(stage) + ": semantics name view '" + sv.view +
                     "' that the capture '" + capture.name + "' lacks");
  return capture.views[v];
}

cv::Mat1f depth_prior(const View& view, const char* stage) {
  const cv::Mat depth = view.depth.load();
  if (depth.empty())
    throw InputError(std::string(stage) + ": view '" + view.name +
                     "' has no depth prior (multi-view fusion and cluster smoothing back-project "
                     "it)");
  return depth;
}

}  // namespace gslift
