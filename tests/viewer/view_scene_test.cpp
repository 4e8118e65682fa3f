// gslift view's run folder (viewer/view_scene.hpp): where the run refined its poses
// (splat.reconstruct refine_poses writes recon/refined_poses.txt), the capture it shows and
// prompts on takes those poses, the ones the model was trained at; poses of another capture are
// refused naming the file.
#include "viewer/view_scene.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/synth/or_capture.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// A run folder as `gslift run` leaves it: run.json naming the capture, recon/model.ply.
fs::path run_folder(const std::string& name, const fs::path& capture) {
  const fs::path run = test::scratch_dir(name);
  nlohmann::json nodes = nlohmann::json::array();
  nodes.push_back({{"id", "capture"}, {"type", "ingest.capture"}, {"params", {{"path", capture}}}});
  nodes.push_back(
      {{"id", "recon"}, {"type", "splat.reconstruct"}, {"params", nlohmann::json::object()}});
  std::ofstream(run / "run.json") << nlohmann::json{{"graph", {{"nodes", nodes}}}}.dump();
  fs::create_directories(run / "recon");
  write_ply(test::two_blobs(), run / "recon" / "model.ply");
  return run;
}

}  // namespace

TEST_CASE("the viewer shows a run at the poses its reconstruction refined", "[viewer]") {
  const fs::path capture_dir = test::scratch_dir("view_scene_poses") / "capture";
  synth::write_or_capture(
      synth::make_settings({{"seed", "1"}, {"views", "4"}, {"width", "96"}, {"height", "72"}}),
      capture_dir);
  const Capture written = load_capture(capture_dir);
  const fs::path run = run_folder("view_scene_run", capture_dir);

  const ViewScene plain = open_run_folder(run);
  CHECK(plain.poses_file.empty());
  CHECK(plain.capture.views[1].pose.t == written.views[1].pose.t);

  ViewPoses refined;
  for (const View& v : written.views) {
    refined.views.push_back(v.name);
    refined.poses.push_back(v.pose);
  }
  refined.poses[1].t += Eigen::Vector3d(0.02, -0.01, 0.005);
  std::ofstream(run / "recon" / "refined_poses.txt") << view_poses_text(refined);
  const ViewScene scene = open_run_folder(run);
  CHECK(scene.poses_file == (run / "recon" / "refined_poses.txt").string());
  CHECK((scene.capture.views[1].pose.t - refined.poses[1].t).norm() < 1e-12);
  CHECK((scene.capture.views[0].pose.t - written.views[0].pose.t).norm() < 1e-12);

  // The same file for a PLY and its capture.
  const ViewScene model = open_model(run / "recon" / "model.ply", capture_dir.string(),
                                     run / "recon" / "refined_poses.txt");
  CHECK((model.capture.views[1].pose.t - refined.poses[1].t).norm() < 1e-12);

  refined.views.pop_back();
  refined.poses.pop_back();
  std::ofstream(run / "recon" / "refined_poses.txt") << view_poses_text(refined);
  CHECK_THROWS_WITH(open_run_folder(run), Contains("refined_poses.txt holds 3 views"));
}
