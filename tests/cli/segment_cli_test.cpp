// `gslift segment` itself: a scripted session through the executable's stdin and stdout, on a
// small synthetic capture and a hand-made feature model.
#include <fstream>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include "base/input_file.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
namespace fs = std::filesystem;

namespace {

// A small capture written by `gslift synth` into dir/capture, and dir/model.ply: 64 Gaussians on a
// grid around the room's centre, Gaussian g with a 1 on feature axis feature_axis(g).
void write_capture_and_grid(const fs::path& dir, int feature_dim,
                            const std::function<int(int)>& feature_axis) {
  REQUIRE(run_command(std::string(GSLIFT_BINARY) + " synth --out '" + (dir / "capture").string() +
                      "' --width 96 --height 72 --views 4")
              .code == exit_code::kOk);
  GaussianModel model;
  model.resize(64);
  model.feature_dim = feature_dim;
  model.features.assign(64 * feature_dim, 0.f);
  for (int g = 0; g < 64; ++g) {
    model.means[3 * g + 0] = -1.5f + 0.4f * (g % 8);
    model.means[3 * g + 1] = -1.5f + 0.4f * (g / 8);
    model.means[3 * g + 2] = 1.f;
    for (int a = 0; a < 3; ++a) model.log_scales[3 * g + a] = -1.5f;
    model.opacity_logits[g] = 2.f;
    model.features[feature_dim * g + feature_axis(g)] = 1.f;
  }
  write_ply(model, dir / "model.ply");
}

}  // namespace

TEST_CASE("gslift segment answers a scripted session line by line", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_segment");
  const std::string binary = GSLIFT_BINARY;
  // Two feature directions, alternating along the grid.
  write_capture_and_grid(dir, 2, [](int g) { return g % 2; });
  std::ofstream(dir / "prompts.jsonl")
      << R"({"name": "a", "view": "cam_00", "positive": [[48, 36]], "output": ")"
      << (dir / "out").string() << R"(", "views": "all"})"
      << "\n"
      << R"({"view": "cam_00", "positive": [[500, 36]]})"
      << "\n"
      << R"({"name": "b", "kind": "mask", "view": "cam_00"})"
      << "\n"
      << R"({"name": "c", "view": "cam_01", "positive": [[10, 10]], "negative": [[20, 20]]})"
      << "\n";
  const auto r =
      run_command(binary + " segment '" + (dir / "model.ply").string() + "' --input '" +
                  (dir / "capture").string() + "' < '" + (dir / "prompts.jsonl").string() + "'");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  std::vector<nlohmann::json> replies;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] == '{') replies.push_back(nlohmann::json::parse(line));
  REQUIRE(replies.size() == 4);
  CHECK(replies[0]["ok"] == true);
  CHECK(replies[0]["views"].size() == 4);
  CHECK(fs::exists(dir / "out/cam_03__a_mask.png"));
  CHECK(replies[1]["ok"] == false);  // pixel outside the 96x72 view
  CHECK(replies[2]["ok"] == false);  // a mask prompt without its mask
  CHECK(replies[3]["ok"] == true);
  CHECK(replies[3]["latency_ms"].get<double>() >= 0);
  // Usage errors: no model, no capture.
  CHECK(run_command(binary + " segment").code == exit_code::kUsage);
  CHECK(run_command(binary + " segment '" + (dir / "model.ply").string() + "'").code ==
        exit_code::kUsage);
  // Bad option values are usage errors: they exited 70 (nan, 1e308), selected everything (-1) or
  // were accepted and failed every prompt (downscale 100000).
  const std::string session = binary + " segment '" + (dir / "model.ply").string() + "' --input '" +
                              (dir / "capture").string() + "'";
  for (const char* bad : {"--tau nan", "--tau 1e308", "--tau -1", "--tau 0.5x", "--tau 1",
                          "--downscale 100000", "--downscale 1.5", "--downscale 0"}) {
    INFO(bad);
    CHECK(run_command(session + " " + bad + " < /dev/null").code == exit_code::kUsage);
  }
  // A read error on stdin (here a folder) is not the end of the prompts.
  const auto failed = run_command(session + " < '" + dir.string() + "'");
  CHECK(failed.code == exit_code::kBadInput);
  CHECK_THAT(failed.output,
             Catch::Matchers::Contains("reading the prompts from stdin failed: Is a directory"));
}

// --poses: a run that refined its poses (recon/refined_poses.txt) is prompted at the poses its
// model was trained at. The same poses as written give the same answer; cam_00 turned by 3
// degrees moves its mask; poses of another capture are refused before any prompt is read.
TEST_CASE("gslift segment --poses answers at the given poses", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_segment_poses");
  const std::string binary = GSLIFT_BINARY;
  // One feature for every Gaussian: a click anywhere on the grid selects all of it.
  write_capture_and_grid(dir, 1, [](int) { return 0; });
  const Capture capture = load_capture(dir / "capture");
  ViewPoses written;
  for (const View& v : capture.views) {
    written.views.push_back(v.name);
    written.poses.push_back(v.pose);
  }
  ViewPoses turned = written;
  turned.poses[0].R =
      Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      turned.poses[0].R;
  ViewPoses other = written;
  other.views[2] = "cam_99";
  std::ofstream(dir / "written.txt") << view_poses_text(written);
  std::ofstream(dir / "turned.txt") << view_poses_text(turned);
  std::ofstream(dir / "other.txt") << view_poses_text(other);
  const auto session = [&](const std::string& poses, const std::string& out) {
    std::ofstream(dir / "prompt.jsonl")
        << R"({"name": "a", "view": "cam_00", "positive": [[48, 36]], "views": ["cam_00"], )"
        << R"("output": ")" << (dir / out).string() << "\"}\n";
    return run_command(binary + " segment '" + (dir / "model.ply").string() + "' --input '" +
                       (dir / "capture").string() + "'" + poses + " < '" +
                       (dir / "prompt.jsonl").string() + "'");
  };
  const auto plain = session("", "plain");
  const auto same = session(" --poses '" + (dir / "written.txt").string() + "'", "same");
  const auto moved = session(" --poses '" + (dir / "turned.txt").string() + "'", "moved");
  INFO(plain.output << same.output << moved.output);
  REQUIRE(plain.code == exit_code::kOk);
  REQUIRE(same.code == exit_code::kOk);
  REQUIRE(moved.code == exit_code::kOk);
  const std::string mask = "cam_00__a_mask.png";
  REQUIRE(fs::exists(dir / "plain" / mask));
  CHECK(read_input_file(dir / "same" / mask) == read_input_file(dir / "plain" / mask));
  CHECK(read_input_file(dir / "moved" / mask) != read_input_file(dir / "plain" / mask));
  const auto refused = session(" --poses '" + (dir / "other.txt").string() + "'", "refused");
  CHECK(refused.code == exit_code::kBadInput);
  CHECK_THAT(refused.output, Catch::Matchers::Contains("other.txt names view 'cam_99'"));
}
