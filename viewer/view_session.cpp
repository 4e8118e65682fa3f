#include "viewer/view_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/inference/filter_3d.hpp"
#include "nodes/inference/selection_output.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

// The degree-0 SH basis constant: colour = kShC0 * dc + 0.5 (3DGS).
constexpr float kShC0 = 0.28209479177387814f;
// A selection is drawn with this much of the highlight colour, everything else at kDimmed of its
// brightness [decision: the object stays recognisable, its surroundings stay readable].
constexpr float kTint = 0.45f, kDimmed = 0.35f;
const float kHighlight[3] = {1.f, 0.85f, 0.1f};
constexpr float kHiddenLogit = -40.f;  // opacity ~ 4e-18: below min_alpha, never drawn

// The Gaussian's degree-0 colour set to `rgb` (0..1) and its view-dependent part dropped.
void set_flat_colour(GaussianModel& m, size_t g, const float rgb[3]) {
  const size_t k = m.sh.size() / m.size();  // K x 3 per Gaussian
  float* sh = &m.sh[g * k];
  std::fill(sh, sh + k, 0.f);
  for (int c = 0; c < 3; ++c) sh[c] = (rgb[c] - 0.5f) / kShC0;
}

// The rendered colour scaled by `s` (SH is linear; the +0.5 offset is folded into the DC term).
void scale_colour(GaussianModel& m, size_t g, float s) {
  const size_t k = m.sh.size() / m.size();
  float* sh = &m.sh[g * k];
  for (size_t i = 3; i < k; ++i) sh[i] *= s;
  for (int c = 0; c < 3; ++c) sh[c] = (s * (kShC0 * sh[c] + 0.5f) - 0.5f) / kShC0;
}

void tint_colour(GaussianModel& m, size_t g) {
  const size_t k = m.sh.size() / m.size();
  float* sh = &m.sh[g * k];
  for (size_t i = 3; i < k; ++i) sh[i] *= 1.f - kTint;
  for (int c = 0; c < 3; ++c) {
    const float colour = (1.f - kTint) * (kShC0 * sh[c] + 0.5f) + kTint * kHighlight[c];
    sh[c] = (colour - 0.5f) / kShC0;
  }
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

ViewSession::ViewSession(ViewScene scene) : scene_(std::move(scene)) {
  if (scene_.model.size() == 0) throw InputError(scene_.title + ": the model has no Gaussians");
  if (scene_.model.feature_dim > 0) {
    PromptOptions options;
    segmenter_ = std::make_unique<PromptSegmenter>(scene_.model, scene_.capture, options);
  }
}

cv::Vec3b ViewSession::instance_colour(int instance) {
  // Golden-angle hues: neighbouring ids get distant colours.
  const int hue = static_cast<int>(std::fmod(instance * 137.508, 360.0) / 2);  // OpenCV: 0..179
  cv::Mat3b hsv(1, 1, cv::Vec3b(static_cast<uchar>(hue), 200, 235)), rgb;
  cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
  return rgb(0, 0);
}

const GaussianModel& ViewSession::display_model(FrameMode mode, const std::vector<int>& hidden) {
  std::string key =
      std::to_string(static_cast<int>(mode)) + "/" + std::to_string(selection_version_) + "/";
  for (int h : hidden) key += std::to_string(h) + ",";
  if (key == display_key_) return display_;
  display_ = scene_.model;
  GaussianModel& m = display_;
  const std::set<int> hide(hidden.begin(), hidden.end());
  const bool has_ids = m.instance_ids.size() == m.size();
  for (size_t g = 0; g < m.size(); ++g) {
    const int id = has_ids ? m.instance_ids[g] : -1;
    if (mode == FrameMode::Instances) {
      float rgb[3] = {0.55f, 0.55f, 0.55f};  // unassigned: grey
      if (id >= 0) {
        const cv::Vec3b c = instance_colour(id);
        for (int i = 0; i < 3; ++i) rgb[i] = c[i] / 255.f;
      }
      set_flat_colour(m, g, rgb);
    }
    if (!selected_.empty()) {
      if (selected_[g])
        tint_colour(m, g);
      else
        scale_colour(m, g, kDimmed);
    }
    if (id >= 0 && hide.count(id)) m.opacity_logits[g] = kHiddenLogit;
  }
  display_key_ = key;
  return display_;
}

cv::Mat3b ViewSession::frame(const FrameRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  check_camera(request.camera, "view frame");
  const GaussianModel& m = display_model(request.mode, request.hidden);
  RenderSettings s;
  s.background = Eigen::Vector3f(0.12f, 0.12f, 0.14f);
  const RenderOutput out = render(m, request.camera, request.pose, s);
  cv::Mat3b image(out.height, out.width);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = out.rgb[(size_t(y) * out.width + x) * 3 + c];
        image(y, x)[c] = static_cast<uchar>(std::clamp(v, 0.f, 1.f) * 255.f + 0.5f);
      }
  return image;
}

void ViewSession::set_selection(std::vector<uint8_t> selected) {
  selected_ = std::move(selected);
  ++selection_version_;
}

SelectionSummary ViewSession::prompt(const Prompt& p, const Camera& camera, const Pose& pose,
                                     double tau) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!segmenter_)
    throw InputError(scene_.title +
                     ": the model has no per-Gaussian features, so a click cannot select");
  const auto t0 = std::chrono::steady_clock::now();
  PromptSelection s = segmenter_->select_in_camera(p, camera, pose, tau);
  SelectionSummary summary;
  summary.selected = s.count;
  set_selection(std::move(s.selected));
  summary.latency_ms = ms_since(t0);
  return summary;
}

SelectionSummary ViewSession::query(const std::string& text) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto t0 = std::chrono::steady_clock::now();
  if (!scene_.encoder) throw InputError(scene_.title + ": the run has no text encoder to ask");
  if (scene_.instance_labels.empty() || scene_.model.instance_ids.size() != scene_.model.size())
    throw InputError(scene_.title + ": the model has no instances to query");
  const TextEncoder& encoder = *scene_.encoder;
  InstanceSet instances;
  instances.labels = scene_.instance_labels;
  instances.prototypes.resize(static_cast<Eigen::Index>(instances.labels.size()), 1);
  instances.semantics.resize(static_cast<Eigen::Index>(instances.labels.size()), encoder.dim());
  for (size_t k = 0; k < instances.labels.size(); ++k)
    instances.semantics.row(static_cast<Eigen::Index>(k)) =
        encoder.encode(instances.labels[k]).transpose();
  TextQueryOptions options;
  for (const std::string& label : instances.labels)
    if (std::find(options.vocabulary.begin(), options.vocabulary.end(), label) ==
        options.vocabulary.end())
      options.vocabulary.push_back(label);
  TextQueryResults results;
  results.queries = {text};
  select_instances(instances, encoder, options, results);
  const std::vector<float> chosen =
      selection_indicator(scene_.model.instance_ids, instances.size(), results.instances[0]);
  std::vector<uint8_t> selected(chosen.size());
  SelectionSummary summary;
  for (size_t g = 0; g < chosen.size(); ++g) {
    selected[g] = chosen[g] > 0;
    summary.selected += selected[g];
  }
  summary.instances = results.instances[0];
  summary.query_class = results.query_classes[0];
  set_selection(std::move(selected));
  summary.latency_ms = ms_since(t0);
  return summary;
}

void ViewSession::clear_selection() {
  std::lock_guard<std::mutex> lock(mutex_);
  set_selection({});
}

int64_t ViewSession::selected_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  int64_t n = 0;
  for (uint8_t s : selected_) n += s;
  return n;
}

cv::Mat1b ViewSession::selection_mask(int view) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (view < 0 || view >= static_cast<int>(scene_.capture.views.size()))
    throw InputError("no capture view " + std::to_string(view));
  const View& v = scene_.capture.views[view];
  auto& masker = maskers_[view];
  if (!masker) masker = std::make_unique<SelectionMasker>(scene_.model, v.camera, v.pose);
  if (selected_.empty()) return cv::Mat1b::zeros(v.camera.height, v.camera.width);
  return masker->mask(selected_, 0.5f);
}

GaussianModel ViewSession::export_selection() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (selected_.empty()) throw InputError("nothing is selected");
  std::vector<int32_t> ids(selected_.size());
  for (size_t g = 0; g < ids.size(); ++g) ids[g] = selected_[g] ? 0 : -1;
  Filter3dOptions options;
  options.grow = false;  // tight: growth would hand the touching floor and walls to the object
  GaussianModel labelled = scene_.model;
  labelled.instance_ids = filter_instances_3d(labelled.means, ids, options).instance_ids;
  GaussianModel object = selected_gaussians(labelled, 0);
  if (object.size() == 0) throw InputError("the 3D filter left none of the selected Gaussians");
  return object;
}

}  // namespace gslift
