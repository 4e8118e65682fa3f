// The in-memory form of a capture: posed views, optional depth prior, sparse points, and ground
// truth when the capture has it (synthetic scenes). Real and synthetic data share this type and
// one on-disk layout (README "Capture layout"); nodes/ingest reads it, nodes/synth writes it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "base/port_type.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/image_source.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct View {
  std::string name;  // image file stem, unique within the capture ("cam_00")
  Camera camera;
  Pose pose;              // world -> camera
  ImageSource rgb;        // CV_8UC3, RGB channel order (not OpenCV's BGR)
  ImageSource depth;      // CV_32FC1 metres, 0 = invalid; the depth prior (MVS / sensor); optional
  bool held_out = false;  // test view (LangOR uses 4 train : 1 test)

  // Ground truth, present for synthetic captures.
  ImageSource gt_instance;  // CV_32SC1 instance id per pixel, 0 = background
  ImageSource gt_semantic;  // CV_32SC1 class id per pixel, 0 = background
  ImageSource gt_depth;     // CV_32FC1 metres, exact
  ImageSource gt_normal;    // CV_32FC3 world-space unit normals
};

// The views a node works on (its `views` param): the training views, the held-out ones, or all.
enum class ViewSet { Train, Test, All };
const EnumNames<ViewSet>& view_set_names();  // train, test, all

struct SparsePoints {
  std::vector<Eigen::Vector3f> xyz;
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> rgb;
  size_t size() const { return xyz.size(); }
};

struct Capture {
  std::string name;
  std::filesystem::path root;  // folder it was read from (empty for in-memory captures)
  // ingest.capture's allow_outside_paths, kept for the nodes that read the annotation folders
  // capture.yaml names (vlm/, sam_box/, sam_auto/) later: false refuses folders outside `root`.
  bool allow_outside_paths = false;
  std::vector<View> views;
  SparsePoints points;
  // Ground-truth vocabulary: class id -> class name (id 0 = background). Empty without GT.
  std::map<int, std::string> classes;
  // Ground-truth instance id -> class id.
  std::map<int, int> instance_class;

  std::vector<int> train_views() const;  // indices of views with held_out == false
  std::vector<int> test_views() const;
  // Indices of the views in `which`, in capture order.
  std::vector<int> views_named(ViewSet which) const;
  int find_view(const std::string& name) const;  // index or -1
};

GSLIFT_PORT_TYPE(Capture, "Capture");

}  // namespace gslift
