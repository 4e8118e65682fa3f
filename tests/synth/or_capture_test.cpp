// The written capture: the layout of docs/capture_format.md, byte-identical at any thread count,
// settings parsed with the preset first.
#include <fstream>
#include <map>
#include <sstream>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "nodes/ingest/coco_rle.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/synth/or_capture.hpp"
#include "nodes/synth/synth_command.hpp"
#include "runtime/exit_codes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::synth;
namespace fs = std::filesystem;

namespace {

OrCaptureSettings small_settings(const std::string& preset = "default") {
  OrCaptureSettings s = make_settings({{"preset", preset},
                                       {"width", "160"},
                                       {"height", "120"},
                                       {"seed", "4"},
                                       {"sparse_points", "2000"}});
  return s;
}

std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    files[fs::relative(e.path(), root).string()] = bytes.str();
  }
  return files;
}

}  // namespace

TEST_CASE("same settings give byte-identical captures with 1 and 2 threads") {
  const fs::path dir = test::scratch_dir("synth_determinism");
  const OrCaptureSettings s = small_settings("hard");  // every simulator and pose noise active
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    write_or_capture(s, dir / "one");
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    write_or_capture(s, dir / "two");
  }
  const auto a = read_tree(dir / "one"), b = read_tree(dir / "two");
  REQUIRE(a.size() > 40);
  CHECK(a.size() == b.size());
  for (const auto& [name, bytes] : a) {
    INFO(name);
    REQUIRE(b.count(name));
    CHECK(bytes == b.at(name));
  }
  // A different seed gives a different capture.
  OrCaptureSettings other = s;
  other.scene.seed = 5;
  write_or_capture(other, dir / "other");
  CHECK(read_tree(dir / "other").at("images/cam_00.png") != a.at("images/cam_00.png"));
}

TEST_CASE("the capture follows docs/capture_format.md and reads back exactly") {
  const fs::path dir = test::scratch_dir("synth_layout") / "cap";
  const OrCaptureSettings s = small_settings();
  write_or_capture(s, dir);
  for (const char* f :
       {"capture.yaml", "synth.yaml", "sparse/0/cameras.txt", "sparse/0/images.txt",
        "sparse/0/points3D.txt", "gt/classes.yaml", "vlm/prompt.txt", "images/cam_00.png",
        "depth/cam_00.png", "gt/instance/cam_04.png", "gt/semantic/cam_04.png",
        "gt/depth/cam_04.tiff", "gt/normal/cam_04.tiff", "vlm/cam_02/round_4.txt",
        "sam_box/cam_02/round_4.json", "sam_auto/cam_03.json"}) {
    INFO(f);
    CHECK(fs::exists(dir / f));
  }
  CHECK_FALSE(fs::exists(dir / "vlm/cam_02/round_5.txt"));
  std::ifstream yaml(dir / "capture.yaml");
  std::stringstream text;
  text << yaml.rdbuf();
  CHECK(text.str().find("held_out: [cam_04]") != std::string::npos);
  CHECK(text.str().find("coords: norm1000") != std::string::npos);

  const ColmapModel model = read_colmap_text(dir / "sparse/0");
  REQUIRE(model.images.size() == 5);
  CHECK(model.cameras.at(1).width == 160);
  CHECK(model.points.size() > 1500);  // 2000 asked, minus the few rays that miss nothing
  // Exact poses when pose noise is off: GT depth back-projected from view 0 lands on the image
  // plane of the same pose.
  const OrScene scene = make_or_scene(s.scene);
  CHECK(model.images[0].pose.R.isApprox(scene.cameras[0].pose.R, 1e-12));

  // One SAM box mask per VLM box, in the same order.
  std::ifstream reply_file(dir / "vlm/cam_01/round_0.txt");
  std::stringstream reply;
  reply << reply_file.rdbuf();
  const std::string r = reply.str();
  const auto boxes = nlohmann::json::parse(r.substr(8, r.size() - 12));
  std::ifstream sam_file(dir / "sam_box/cam_01/round_0.json");
  const auto masks = nlohmann::json::parse(sam_file);
  CHECK(masks.size() == boxes.size());
  CHECK(boxes.size() >= 5);
  std::ifstream auto_file(dir / "sam_auto/cam_01.json");
  const auto autos = nlohmann::json::parse(auto_file);
  REQUIRE(autos.size() >= 5);
  for (const auto& m : autos) {
    // The RLE decodes (with ingest's reader) to a mask of the recorded area and box.
    const cv::Mat1b mask = rle_decode_json(m["segmentation"], "sam_auto");
    REQUIRE(mask.size() == cv::Size(160, 120));
    CHECK(cv::countNonZero(mask) == m["area"].get<int>());
    const cv::Rect b = cv::boundingRect(mask);
    CHECK(m["bbox"] == nlohmann::json({b.x, b.y, b.width, b.height}));
    CHECK(m.contains("granularity"));
  }

  // Label maps and depths round-trip through the shared readers.
  const cv::Mat inst = read_label_map(dir / "gt/instance/cam_00.png");
  double max_id = 0;
  cv::minMaxLoc(inst, nullptr, &max_id);
  CHECK(max_id >= 12);
  const cv::Mat gt = read_float_tiff(dir / "gt/depth/cam_00.tiff");
  const cv::Mat prior = read_depth(dir / "depth/cam_00.png", 1000);
  cv::Mat valid = prior > 0;
  const double rel = cv::norm(prior - gt, cv::NORM_L1, valid) / cv::norm(gt, cv::NORM_L1, valid);
  CHECK(rel > 0.003);  // noisy...
  CHECK(rel < 0.04);   // ...at the default 2 % level
}

TEST_CASE("settings: preset first, explicit knobs win, bad values are named") {
  const OrCaptureSettings s =
      make_settings({{"vlm_miss_rate", "0.5"}, {"preset", "hard"}, {"phase", "closing"}});
  CHECK(s.knobs.vlm_miss_rate == 0.5);
  CHECK(s.knobs.vlm_hallucination_rate == preset_knobs(SynthPreset::Hard).vlm_hallucination_rate);
  CHECK(s.scene.phase == OrPhase::Closing);
  CHECK(capture_name(s) == "or_s0_closing");
  CHECK_THROWS_WITH(
      make_settings({{"phase", "lunch"}}),
      Catch::Contains("phase: 'lunch' is not one of {preparation, surgery, closing}"));
  CHECK_THROWS_WITH(make_settings({{"seed", "-3"}}), Catch::Contains("seed"));
  // The scene's limits are the settings' too (embedded:or?views=9 is bad input, not a failure
  // inside the generator).
  CHECK_THROWS_WITH(make_settings({{"views", "9"}}), Catch::Contains("views must be 4..8"));
  CHECK_THROWS_WITH(make_settings({{"width", "8"}}), Catch::Contains("at least 16x16"));
  // Sizes are checked before narrowing (4294967456 wrapped to 160) and against gslift's own
  // 2^26-pixel image limit (9000 x 9000 was generated; 100000 x 100000 failed inside OpenCV).
  CHECK_THROWS_WITH(make_settings({{"width", "4294967456"}}),
                    Catch::Contains("width: 4294967456 is over the limit of 67108864"));
  CHECK_THROWS_WITH(make_settings({{"views", "4294967300"}}), Catch::Contains("views"));
  CHECK_THROWS_WITH(make_settings({{"width", "9000"}, {"height", "9000"}}),
                    Catch::Contains("9000 x 9000 is not from 1 x 1 to 67108864 pixels"));
  CHECK_THROWS_WITH(make_settings({{"width", "100000"}, {"height", "100000"}}),
                    Catch::Contains("100000 x 100000"));
  CHECK_THROWS_WITH(make_settings({{"height", "0"}}), Catch::Contains("x 0 is not"));
  CHECK(make_settings({{"width", "8192"}, {"height", "8192"}}).scene.width == 8192);
}

TEST_CASE("gslift synth command: usage errors and a written capture") {
  const fs::path dir = test::scratch_dir("synth_command");
  auto run = [](std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return synth_main(static_cast<int>(argv.size()), argv.data());
  };
  CHECK(run({"synth", "--help"}) == exit_code::kOk);
  CHECK(run({"synth"}) == exit_code::kUsage);
  CHECK(run({"synth", "--out", (dir / "x").string(), "--bogus", "1"}) == exit_code::kUsage);
  CHECK(run({"synth", "--out", (dir / "x").string(), "--set", "nope=1"}) == exit_code::kUsage);
  CHECK(run({"synth", "--out", (dir / "c").string(), "--width", "96", "--height", "72", "--views",
             "4", "--set", "vlm_rounds=2"}) == exit_code::kOk);
  CHECK(fs::exists(dir / "c/vlm/cam_03/round_1.txt"));
  CHECK_FALSE(fs::exists(dir / "c/vlm/cam_03/round_2.txt"));
  // An existing capture is never overwritten.
  CHECK(run({"synth", "--out", (dir / "c").string()}) == exit_code::kUsage);
}
