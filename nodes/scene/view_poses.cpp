#include "nodes/scene/view_poses.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <locale>
#include <sstream>

#include <Eigen/Geometry>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

std::string view_poses_text(const ViewPoses& poses) {
  std::ostringstream text;
  text.imbue(std::locale::classic());
  text.precision(17);
  text << "# poses refined by splat.reconstruct (refine_poses): view qw qx qy qz tx ty tz, world "
          "-> camera\n";
  for (size_t v = 0; v < poses.views.size(); ++v) {
    const Eigen::Quaterniond q(poses.poses[v].R);
    const Eigen::Vector3d& t = poses.poses[v].t;
    text << poses.views[v] << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
         << t.x() << ' ' << t.y() << ' ' << t.z() << '\n';
  }
  return text.str();
}

ViewPoses parse_view_poses(const std::string& text, const std::string& source) {
  ViewPoses out;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    fields.imbue(std::locale::classic());
    std::string name;
    double v[7];
    fields >> name;
    for (double& x : v) fields >> x;
    std::string rest;
    const bool finite =
        std::all_of(std::begin(v), std::end(v), [](double x) { return std::isfinite(x); });
    if (fields.fail() || (fields >> rest) || !finite)
      throw InputError(source + ":" + std::to_string(number) +
                       ": expected 'view qw qx qy qz tx ty tz' (8 fields, finite numbers)");
    const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
    if (std::abs(q.norm() - 1) > 1e-6)
      throw InputError(source + ":" + std::to_string(number) + ": the rotation of view '" + name +
                       "' is no unit quaternion (norm " + std::to_string(q.norm()) + ")");
    Pose pose;
    pose.R = q.normalized().toRotationMatrix();
    pose.t = Eigen::Vector3d(v[4], v[5], v[6]);
    out.views.push_back(name);
    out.poses.push_back(pose);
  }
  if (out.views.empty()) throw InputError(source + ": holds no pose");
  return out;
}

ViewPoses read_view_poses(const std::filesystem::path& file) {
  return parse_view_poses(read_input_file(file, "poses file"), file.string());
}

void apply_view_poses(Capture& capture, const ViewPoses& poses, const std::string& source) {
  if (poses.views.size() != capture.views.size())
    throw InputError(source + " holds " + std::to_string(poses.views.size()) + " views, capture '" +
                     capture.name + "' has " + std::to_string(capture.views.size()));
  for (size_t v = 0; v < capture.views.size(); ++v)
    if (poses.views[v] != capture.views[v].name)
      throw InputError(source + " names view '" + poses.views[v] + "' where capture '" +
                       capture.name + "' has '" + capture.views[v].name +
                       "' (poses of another capture)");
  // Checked first, so that a refused file leaves every pose as it was.
  for (size_t v = 0; v < capture.views.size(); ++v) capture.views[v].pose = poses.poses[v];
}

}  // namespace gslift
