// refined_poses.txt (nodes/scene/view_poses.hpp): written, read back to double precision, and put
// into a capture; malformed lines and poses of another capture are refused naming the file.
#include "nodes/scene/view_poses.hpp"

#include <Eigen/Geometry>

#include "base/errors.hpp"
#include "nodes/scene/capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

Pose pose_of(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  Pose p;
  p.R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  p.t = t;
  return p;
}

Capture two_view_capture() {
  Capture c;
  c.name = "room";
  for (const char* name : {"cam_00", "cam_01"}) {
    View v;
    v.name = name;
    c.views.push_back(v);
  }
  return c;
}

}  // namespace

TEST_CASE("view poses round-trip through refined_poses.txt to double precision", "[scene]") {
  ViewPoses poses;
  poses.views = {"cam_00", "cam_01"};
  poses.poses = {pose_of(0.3, {1, 2, 3}, {0.1, -2.5, 3.25}),
                 pose_of(2.9, {-1, 0.5, 0.2}, {1e-3, 4.0, -7.125})};
  const ViewPoses back = parse_view_poses(view_poses_text(poses), "poses.txt");
  REQUIRE(back.views == poses.views);
  for (size_t v = 0; v < poses.poses.size(); ++v) {
    CHECK((back.poses[v].R - poses.poses[v].R).cwiseAbs().maxCoeff() < 1e-14);
    CHECK((back.poses[v].t - poses.poses[v].t).cwiseAbs().maxCoeff() == 0);
  }
  Capture capture = two_view_capture();
  apply_view_poses(capture, back, "poses.txt");
  CHECK(capture.views[1].pose.t.isApprox(Eigen::Vector3d(1e-3, 4.0, -7.125)));
}

TEST_CASE("a malformed refined_poses.txt is refused naming its file and line", "[scene]") {
  const std::string good = "cam_00 1 0 0 0 0 0 0\n";
  CHECK_THROWS_WITH(parse_view_poses("# comment\n" + good + "cam_01 1 0 0 0 0 0\n", "p.txt"),
                    Contains("p.txt:3") && Contains("8 fields"));
  CHECK_THROWS_WITH(parse_view_poses(good + "cam_01 1 0 0 0 0 0 0 9\n", "p.txt"),
                    Contains("p.txt:2"));
  CHECK_THROWS_WITH(parse_view_poses("cam_00 1 0 0 0 nan 0 0\n", "p.txt"), Contains("p.txt:1"));
  CHECK_THROWS_WITH(parse_view_poses("cam_00 2 0 0 0 0 0 0\n", "p.txt"),
                    Contains("p.txt:1") && Contains("no unit quaternion"));
  CHECK_THROWS_WITH(parse_view_poses("# only a comment\n", "p.txt"), Contains("holds no pose"));
  CHECK_THROWS_WITH(read_view_poses("/nonexistent/refined_poses.txt"),
                    Contains("/nonexistent/refined_poses.txt") && Contains("does not exist"));
  const auto dir = test::scratch_dir("view_poses_dir");
  CHECK_THROWS_WITH(read_view_poses(dir), Contains("is a directory"));
}

TEST_CASE("poses of another capture are refused, the capture left as it was", "[scene]") {
  Capture capture = two_view_capture();
  const ViewPoses one = parse_view_poses("cam_00 1 0 0 0 1 2 3\n", "p.txt");
  CHECK_THROWS_WITH(apply_view_poses(capture, one, "p.txt"),
                    Contains("p.txt holds 1 views") && Contains("'room' has 2"));
  const ViewPoses renamed =
      parse_view_poses("cam_00 1 0 0 0 1 2 3\ncam_09 1 0 0 0 0 0 0\n", "p.txt");
  CHECK_THROWS_WITH(apply_view_poses(capture, renamed, "p.txt"), Contains("names view 'cam_09'"));
  CHECK(capture.views[0].pose.t.isZero());
}
