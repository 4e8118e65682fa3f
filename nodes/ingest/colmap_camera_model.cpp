#include "nodes/ingest/colmap_camera_model.hpp"

#include <array>
#include <stdexcept>

#include "base/errors.hpp"

namespace gslift {
namespace {

constexpr std::array<ColmapCameraModel, 6> kModels{{{0, "SIMPLE_PINHOLE", 3},
                                                    {1, "PINHOLE", 4},
                                                    {2, "SIMPLE_RADIAL", 4},
                                                    {3, "RADIAL", 5},
                                                    {4, "OPENCV", 8},
                                                    {6, "FULL_OPENCV", 12}}};

std::string supported() {
  std::string s;
  for (const auto& m : kModels)
    s += (s.empty() ? "" : ", ") + std::string(m.name) + " (" + std::to_string(m.id) + ")";
  return s;
}

}  // namespace

const ColmapCameraModel& colmap_camera_model(int id, const std::string& where) {
  for (const auto& m : kModels)
    if (m.id == id) return m;
  throw InputError(where + ": unsupported COLMAP camera model id " + std::to_string(id) +
                   "; supported: " + supported());
}

const ColmapCameraModel& colmap_camera_model(const std::string& name, const std::string& where) {
  for (const auto& m : kModels)
    if (name == m.name) return m;
  throw InputError(where + ": unsupported COLMAP camera model '" + name +
                   "'; supported: " + supported());
}

Camera camera_from_colmap(const ColmapCameraModel& model, int width, int height,
                          const std::vector<double>& p, const std::string& where) {
  if (static_cast<int>(p.size()) != model.num_params)
    throw InputError(where + ": camera model " + model.name + " takes " +
                     std::to_string(model.num_params) + " parameters, got " +
                     std::to_string(p.size()));
  Camera c;
  c.width = width;
  c.height = height;
  const bool single_focal = model.id == 0 || model.id == 2 || model.id == 3;
  const int k = single_focal ? 3 : 4;  // index of the first distortion parameter
  c.fx = p[0];
  c.fy = single_focal ? p[0] : p[1];
  c.cx = p[k - 2];
  c.cy = p[k - 1];
  switch (model.id) {
    case 2:  // SIMPLE_RADIAL: k1 only
      c.distortion = {p[3], 0, 0, 0};
      break;
    case 3:  // RADIAL: k1 k2
      c.distortion = {p[3], p[4], 0, 0};
      break;
    case 4:  // OPENCV: k1 k2 p1 p2
      c.distortion.assign(p.begin() + 4, p.end());
      break;
    case 6:  // k1 k2 p1 p2 k3 k4 k5 k6, OpenCV's order; without k4..k6 the 5-term model
      c.distortion.assign(p.begin() + 4,
                          p[9] != 0 || p[10] != 0 || p[11] != 0 ? p.end() : p.begin() + 9);
      break;
    default:
      break;
  }
  check_camera(c, where);  // size, finite positive focal lengths (the binary model has NaNs too)
  return c;
}

std::pair<std::string, std::vector<double>> colmap_params_of(const Camera& c) {
  std::vector<double> p{c.fx, c.fy, c.cx, c.cy};
  const auto& d = c.distortion;
  if (d.empty()) return {"PINHOLE", p};
  p.insert(p.end(), d.begin(), d.end());
  if (d.size() == 4) return {"OPENCV", p};
  if (d.size() == 5) {
    p.insert(p.end(), {0.0, 0.0, 0.0});
    return {"FULL_OPENCV", p};
  }
  if (d.size() == 8) return {"FULL_OPENCV", p};
  throw std::invalid_argument("COLMAP writes distortion of 0, 4, 5 or 8 coefficients, got " +
                              std::to_string(d.size()));
}

}  // namespace gslift
