#include "nodes/ingest/rgbd_folders.hpp"

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "nodes/ingest/numeric_text.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

namespace fs = std::filesystem;

Eigen::Matrix4d c2w_from(const std::vector<double>& v, size_t offset) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = v[offset + 4 * r + c];
  return m;
}

std::vector<fs::path> sorted_entries(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::vector<ViewFiles> read_replica_views(const fs::path& folder) {
  fs::path params = folder / "cam_params.json";
  if (!fs::exists(params)) params = folder.parent_path() / "cam_params.json";
  const std::string text = read_input_file(params, "cam_params.json");
  Camera cam;
  double scale = 0;
  try {
    const auto j = parse_json(text).at("camera");
    // As 64-bit integers and checked before narrowing: get<int> wraps 1e10.
    const long long w = j.at("w").get<long long>(), h = j.at("h").get<long long>();
    check_image_size(w, h, params.string());
    cam.width = static_cast<int>(w);
    cam.height = static_cast<int>(h);
    cam.fx = j.at("fx").get<double>();
    cam.fy = j.at("fy").get<double>();
    cam.cx = j.at("cx").get<double>();
    cam.cy = j.at("cy").get<double>();
    scale = j.at("scale").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(params.string() +
                     ": expected {\"camera\": {w, h, fx, fy, cx, cy, scale}}: " + e.what());
  }
  check_camera(cam, params.string());
  const fs::path traj = folder / "traj.txt";
  const std::vector<double> poses = read_numbers_file(traj.string());
  if (poses.size() % 16 != 0)
    throw InputError(traj.string() + ": expected 16 numbers per line (a 4x4 camera-to-world)");

  std::vector<ViewFiles> views;
  const fs::path results = folder / "results";
  if (!fs::is_directory(results)) throw InputError(results.string() + ": folder not found");
  for (const auto& p : sorted_entries(results)) {
    unsigned index = 0;
    char tail = 0;
    const std::string file = p.filename().string();
    if (std::sscanf(file.c_str(), "frame%6u.jp%c", &index, &tail) != 2) continue;
    if ((index + 1) * 16 > poses.size())
      throw InputError(traj.string() + ": no pose for " + p.string());
    ViewFiles v;
    v.name = p.stem().string();
    v.camera = cam;
    v.pose = Pose::from_camera_to_world(c2w_from(poses, index * 16));
    v.rgb = p;
    char depth[32];
    std::snprintf(depth, sizeof depth, "depth%06u.png", index);
    if (fs::exists(results / depth)) {
      v.depth = results / depth;
      v.depth_scale = scale;
    }
    views.push_back(std::move(v));
  }
  return views;
}

std::vector<ViewFiles> read_3dmatch_views(const fs::path& folder) {
  const fs::path kfile = folder / "camera-intrinsics.txt";
  const std::vector<double> k = read_numbers_file(kfile.string());
  if (k.size() != 9) throw InputError(kfile.string() + ": expected a 3x3 matrix (9 numbers)");
  Camera cam;
  cam.fx = k[0];
  cam.cx = k[2];
  cam.fy = k[4];
  cam.cy = k[5];
  std::vector<ViewFiles> views;
  for (const auto& seq : sorted_entries(folder)) {
    if (!fs::is_directory(seq) || seq.filename().string().rfind("seq-", 0) != 0) continue;
    for (const auto& p : sorted_entries(seq)) {
      const std::string file = p.filename().string();
      const std::string suffix = ".color.png";
      if (file.size() <= suffix.size() ||
          file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      const std::string frame = file.substr(0, file.size() - suffix.size());
      if (cam.width == 0) {
        const cv::Mat probe = read_image(p);
        cam.width = probe.cols;
        cam.height = probe.rows;
      }
      const fs::path pose_file = seq / (frame + ".pose.txt");
      const std::vector<double> pose = read_numbers_file(pose_file.string());
      if (pose.size() != 16)
        throw InputError(pose_file.string() + ": expected a 4x4 matrix (16 numbers)");
      ViewFiles v;
      v.name = seq.filename().string() + "_" + frame;
      v.camera = cam;
      v.pose = Pose::from_camera_to_world(c2w_from(pose, 0));
      v.rgb = p;
      if (fs::exists(seq / (frame + ".depth.png"))) {
        v.depth = seq / (frame + ".depth.png");
        v.depth_scale = 1000;
      }
      views.push_back(std::move(v));
    }
  }
  if (views.empty()) throw InputError(folder.string() + ": no seq-*/frame-*.color.png found");
  return views;
}

}  // namespace gslift
