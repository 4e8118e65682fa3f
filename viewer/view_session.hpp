// The state behind one `gslift view` page, without HTTP: frames of the scene from any camera
// (gslift's own rasterizer, so the picture is what the metrics measured), instances coloured or
// hidden, and one current selection made by a SAGA prompt or a LangOR text query, highlighted in
// the frames, rendered as a mask in a capture view, and exported as a filtered PLY.
// Thread-safe: every call holds the session's lock (the rasterizer runs in parallel inside it).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/inference/prompt_segmentation.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "viewer/view_scene.hpp"

namespace gslift {

enum class FrameMode { Colour, Instances };

struct FrameRequest {
  Camera camera;
  Pose pose;
  FrameMode mode = FrameMode::Colour;
  std::vector<int> hidden;  // instance ids not drawn
};

struct SelectionSummary {
  int64_t selected = 0;        // Gaussians
  double latency_ms = 0;       // from the request to the selection (no frame)
  std::string query_class;     // text queries: the class the query landed on ("" when none)
  std::vector<int> instances;  // text queries: the instances chosen
};

class ViewSession {
 public:
  explicit ViewSession(ViewScene scene);

  const ViewScene& scene() const { return scene_; }
  // RGB colour per instance id (0..255), fixed by the id: legend and frames agree.
  static cv::Vec3b instance_colour(int instance);

  // The frame, CV_8UC3 in RGB order. The selection, when there is one, is drawn bright with a
  // yellow tint and everything else dimmed.
  cv::Mat3b frame(const FrameRequest& request);

  // A point or scribble prompt in the request's camera, thresholded at tau. Throws InputError
  // for a bad prompt, or when the model has no per-Gaussian features.
  SelectionSummary prompt(const Prompt& prompt, const Camera& camera, const Pose& pose, double tau);
  // The LangOR text query: the closed set of the query and every instance label, the chosen
  // instances' Gaussians become the selection. Throws InputError without an encoder or instances.
  SelectionSummary query(const std::string& text);
  void clear_selection();
  int64_t selected_count() const;

  // 255 where the selection's accumulated alpha reaches 0.5 in capture view `view`.
  cv::Mat1b selection_mask(int view);
  // The selected Gaussians after SAGA's 3D filter (inference.filter_3d without growth: outliers
  // and small pieces dropped, nothing added), as a model of their own. Throws InputError when
  // nothing is selected or nothing is left.
  GaussianModel export_selection();

 private:
  void set_selection(std::vector<uint8_t> selected);
  const GaussianModel& display_model(FrameMode mode, const std::vector<int>& hidden);

  mutable std::mutex mutex_;
  ViewScene scene_;
  std::unique_ptr<PromptSegmenter> segmenter_;  // null without features
  std::vector<uint8_t> selected_;               // per Gaussian; empty = no selection
  uint64_t selection_version_ = 0;
  std::map<int, std::unique_ptr<SelectionMasker>> maskers_;  // per capture view, on first use
  // The last model drawn and what it was made for: a frame at a new camera reuses it.
  GaussianModel display_;
  std::string display_key_;
};

}  // namespace gslift
