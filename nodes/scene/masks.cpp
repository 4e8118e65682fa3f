#include "nodes/scene/masks.hpp"

#include "base/errors.hpp"

namespace gslift {

std::vector<MaskView> training_mask_views(const Capture& capture, const MaskSet& masks) {
  std::vector<MaskView> out;
  for (size_t v = 0; v < masks.views.size(); ++v) {
    const ViewMasks& vm = masks.views[v];
    const int index = capture.find_view(vm.view);
    if (index < 0)
      throw InputError("masks name the view '" + vm.view + "', which is not in the capture '" +
                       capture.name + "'");
    const Camera& camera = capture.views[index].camera;
    for (size_t k = 0; k < vm.masks.size(); ++k) {
      const cv::Mat1b& px = vm.masks[k].pixels;
      if (px.cols != camera.width || px.rows != camera.height)
        throw InputError("mask " + std::to_string(k) + " of view '" + vm.view + "' is " +
                         std::to_string(px.cols) + "x" + std::to_string(px.rows) +
                         " but the view is " + std::to_string(camera.width) + "x" +
                         std::to_string(camera.height));
    }
    if (!capture.views[index].held_out) out.push_back({static_cast<int>(v), index});
  }
  if (out.empty())
    throw InputError("no training view of the capture '" + capture.name + "' has masks");
  return out;
}

}  // namespace gslift
