#include "viewer/view_scene.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/scene/context_prompt.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/text/hashing_text_encoder.hpp"
#include "nodes/text/lexical_text_encoder.hpp"

namespace gslift {
namespace fs = std::filesystem;
namespace {

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot read it");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

int instance_count(const GaussianModel& model) {
  int count = 0;
  for (int32_t id : model.instance_ids) count = std::max(count, id + 1);
  return count;
}

// Labels from a model's class ids (the capture's ground-truth vocabulary), else "instance <k>".
std::vector<std::string> default_labels(const GaussianModel& model, const Capture& capture) {
  std::vector<std::string> labels(instance_count(model));
  for (size_t k = 0; k < labels.size(); ++k) labels[k] = "instance " + std::to_string(k);
  if (model.class_ids.size() != model.size()) return labels;
  for (size_t g = 0; g < model.size(); ++g) {
    const int32_t id = model.instance_ids[g];
    const auto cls = capture.classes.find(model.class_ids[g]);
    if (id >= 0 && cls != capture.classes.end()) labels[id] = cls->second;
  }
  return labels;
}

CaptureOptions capture_options(const nlohmann::json& params) {
  CaptureOptions o;
  o.holdout_every = params.value("holdout_every", o.holdout_every);
  o.skip_missing_images = params.value("skip_missing_images", o.skip_missing_images);
  o.downscale = params.value("downscale", o.downscale);
  o.undistort = params.value("undistort", o.undistort);
  o.undistort_crop = params.value("undistort_crop", o.undistort_crop);
  o.allow_outside_paths = params.value("allow_outside_paths", o.allow_outside_paths);
  return o;
}

std::shared_ptr<const TextEncoder> run_encoder(const nlohmann::json& params) {
  const std::string kind = params.value("kind", "hashing");
  if (kind == "lexical")
    return std::make_shared<const LexicalTextEncoder>(
        load_vocabulary(params.value("vocabulary", "")), params.value("dim", 384));
  if (kind == "hashing")
    return std::make_shared<const HashingTextEncoder>(params.value("dim", 384));
  return nullptr;  // table and embeddings encoders need files or a server the run had
}

// The capture's poses replaced by those of a refined_poses.txt (the ones the model was trained at).
void take_poses(ViewScene& scene, const fs::path& file) {
  apply_view_poses(scene.capture, read_view_poses(file), file.string());
  scene.poses_file = file.string();
}

}  // namespace

ViewScene open_run_folder(const fs::path& run) {
  const fs::path record = run / "run.json";
  if (!fs::is_regular_file(record))
    throw InputError(run.string() +
                     ": not a run folder (no run.json; `gslift run --out` writes one)");
  const nlohmann::json j = parse_json(read_text(record));
  const nlohmann::json& nodes = j.at("graph").at("nodes");
  ViewScene scene;
  scene.title = run.string();
  fs::path model_file;
  std::string capture_path;
  nlohmann::json capture_params, encoder_params;
  for (auto it = nodes.rbegin(); it != nodes.rend(); ++it) {
    const std::string id = it->value("id", ""), type = it->value("type", "");
    for (const char* name : {"segmented.ply", "model.ply"})
      if (model_file.empty() && !id.empty() && fs::is_regular_file(run / id / name))
        model_file = run / id / name;
    if (type == "ingest.capture" && capture_path.empty()) {
      capture_params = it->value("params", nlohmann::json::object());
      capture_path = capture_params.value("path", "");
    }
    if (type == "text.encoder") encoder_params = it->value("params", nlohmann::json::object());
  }
  if (model_file.empty())
    throw InputError(run.string() + ": no node folder holds segmented.ply or model.ply");
  if (capture_path.empty())
    throw InputError(record.string() + ": the graph has no ingest.capture node with a path");
  scene.model = read_ply(model_file);
  scene.capture = load_capture(resolve_capture_path(capture_path), capture_options(capture_params));
  for (const auto& node : nodes) {
    const fs::path file = run / node.value("id", "") / "refined_poses.txt";
    if (!node.value("id", "").empty() && fs::is_regular_file(file)) take_poses(scene, file);
  }
  scene.instance_labels = default_labels(scene.model, scene.capture);
  for (const auto& node : nodes) {
    const fs::path file = run / node.value("id", "") / "instances.json";
    if (node.value("id", "").empty() || !fs::is_regular_file(file)) continue;
    for (const auto& instance : parse_json(read_text(file))) {
      const int k = instance.value("instance", -1);
      if (k >= 0 && k < static_cast<int>(scene.instance_labels.size()))
        scene.instance_labels[k] = instance.value("label", scene.instance_labels[k]);
    }
  }
  if (!encoder_params.is_null()) scene.encoder = run_encoder(encoder_params);
  for (const auto& node : nodes)
    if (fs::is_regular_file(run / node.value("id", "") / "metrics.md") &&
        !node.value("id", "").empty())
      scene.metrics_markdown = read_text(run / node.value("id", "") / "metrics.md");
  return scene;
}

ViewScene open_model(const fs::path& ply, const std::string& capture, const fs::path& poses_file) {
  ViewScene scene;
  scene.title = ply.string();
  scene.model = read_ply(ply);
  scene.capture = load_capture(resolve_capture_path(capture));
  if (!poses_file.empty()) take_poses(scene, poses_file);
  scene.instance_labels = default_labels(scene.model, scene.capture);
  return scene;
}

}  // namespace gslift
