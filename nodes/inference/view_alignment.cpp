#include "nodes/inference/view_alignment.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/training_targets.hpp"

namespace gslift {

const ParamTable<MaskAlignment>& mask_alignment_param_table() {
  static const ParamTable<MaskAlignment> table =
      ParamTable<MaskAlignment>()
          .add("align_to_photo", &MaskAlignment::to_photo,
               "move each view's answers by the 2D shift that registers the model's render there "
               "to the view's photo (for captures whose poses are off by a few pixels)")
          .add("align_min_gain", &MaskAlignment::min_gain,
               "align_to_photo: the gain in image correlation a shift must bring to be applied "
               "(0.003: chosen on the mixed dev rooms)",
               0, 1);
  return table;
}

PhotoAlignment view_photo_alignment(const GaussianModel& model, const View& view,
                                    const MaskAlignment& align) {
  if (!align.to_photo || !view.rgb.present()) return {};
  // The view's photo and the model's colours rendered at its pose, as gray images in [0, 1].
  const RenderOutput r = render(model, view.camera, view.pose, RenderSettings{});
  cv::Mat3f rgb(r.height, r.width);
  std::copy(r.rgb.begin(), r.rgb.end(), reinterpret_cast<float*>(rgb.data));
  cv::Mat1f rendered, photo;
  cv::cvtColor(rgb, rendered, cv::COLOR_RGB2GRAY);
  cv::Mat photo8;
  cv::cvtColor(load_view_rgb(view), photo8, cv::COLOR_RGB2GRAY);
  photo8.convertTo(photo, CV_32F, 1.0 / 255);
  return align_render_to_photo(rendered, photo, align.min_gain);
}

}  // namespace gslift
