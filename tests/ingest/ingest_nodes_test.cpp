// The ingest nodes through the executor, on inline graphs.
#include <fstream>

#include "nodes/ingest/capture_provider.hpp"
#include "nodes/ingest/register.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "runtime/executor.hpp"
#include "runtime/node.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

fs::path capture_with_replies(const std::string& name) {
  const fs::path dir = test::write_small_capture(name, "vlm: {coords: pixels}\n");
  fs::create_directories(dir / "vlm/cam_01");
  fs::create_directories(dir / "sam_box/cam_01");
  std::ofstream(dir / "vlm/cam_01/round_0.txt")
      << "[{\"bbox_2d\": [0, 0, 4, 6], \"label\": \"nurse\"}]";
  std::ofstream(dir / "sam_box/cam_01/round_0.json") << "[{\"size\": [6, 8], \"counts\": [6, 42]}]";
  // SAM's automatic masks found nothing in cam_02 (an empty list): the capture has them, so the
  // preflight lets kind auto run, and its masks are empty.
  fs::create_directories(dir / "sam_auto");
  std::ofstream(dir / "sam_auto/cam_02.json") << "[]";
  return dir;
}

RunResult run(const std::string& path, const std::string& sam_kind,
              const std::string& sam_inputs = ", boxes: vlm.boxes") {
  Registry registry;
  register_ingest_nodes(registry);
  return run_graph_text(R"(
graph: ingest
nodes:
  capture: {type: ingest.capture, params: {path: ")" +
                            path + R"(", downscale: 2, holdout_every: 2}}
  vlm:     {type: ingest.vlm, in: {capture: capture.capture}}
  masks:   {type: ingest.sam_masks, in: {capture: capture.capture)" +
                            sam_inputs + R"(}, params: {kind: )" + sam_kind + R"(}}
)",
                        registry);
}

}  // namespace

TEST_CASE("ingest.capture, ingest.vlm and ingest.sam_masks on a capture folder") {
  const fs::path dir = capture_with_replies("ingest_nodes");
  const RunResult r = run(dir.string(), "box");
  INFO((r.error ? r.error->str() : std::string()));
  REQUIRE(r.ok());
  const auto capture = r.values.at("capture.capture").get<Capture>();
  REQUIRE(capture->views.size() == 3);
  CHECK(capture->views[0].camera.width == 4);
  CHECK(capture->test_views() == std::vector<int>{0, 2});
  CHECK(std::get<double>(r.node("capture")->records.at("views")) == 3);

  const auto boxes = r.values.at("vlm.boxes").get<BoxSet>();
  REQUIRE(boxes->views[1].boxes.size() == 1);
  CHECK(boxes->views[1].boxes[0].x2 == 2);  // pixels of the 8 x 6 image, view at half size

  const auto masks = r.values.at("masks.masks").get<MaskSet>();
  REQUIRE(masks->views[1].masks.size() == 1);
  CHECK(masks->views[1].masks[0].label == "nurse");
  CHECK(masks->views[1].masks[0].pixels.size() == cv::Size(4, 3));
}

TEST_CASE(
    "ingest.sam_masks reads only what is wired: kind box needs boxes, kind auto refuses them") {
  const fs::path dir = capture_with_replies("ingest_nodes_sam_contract");
  const RunResult box = run(dir.string(), "box", "");
  REQUIRE_FALSE(box.ok());
  CHECK_THAT(box.error->message, Contains("kind box needs the input 'boxes'"));
  const RunResult automatic = run(dir.string(), "auto");
  REQUIRE_FALSE(automatic.ok());
  CHECK_THAT(automatic.error->message, Contains("kind auto") && Contains("takes no boxes"));
  const RunResult auto_alone = run(dir.string(), "auto", "");
  INFO((auto_alone.error ? auto_alone.error->str() : std::string()));
  CHECK(auto_alone.ok());
}

TEST_CASE("ingest.capture resolves scheme paths through registered providers") {
  const fs::path dir = capture_with_replies("ingest_nodes_scheme");
  std::string asked;
  register_capture_provider("testcapture", [&](const std::string& spec) {
    asked = spec;
    return dir;
  });
  CHECK(resolve_capture_path("testcapture:or?seed=3") == dir);
  CHECK(asked == "or?seed=3");
  // Plain paths, including ones with a colon later on or a drive letter, stay paths.
  CHECK(resolve_capture_path("/data/a:b") == fs::path("/data/a:b"));
  CHECK(resolve_capture_path("C:/captures/x") == fs::path("C:/captures/x"));
  CHECK_THROWS_WITH(resolve_capture_path("nosuch:or"),
                    Contains("nosuch:") && Contains("testcapture:"));

  const RunResult ok = run("testcapture:x", "auto", "");
  INFO((ok.error ? ok.error->str() : std::string()));
  REQUIRE(ok.ok());
  CHECK(ok.values.at("masks.masks").get<MaskSet>()->views[0].masks.empty());

  const RunResult bad = run("nosuch:or", "auto", "");
  REQUIRE_FALSE(bad.ok());
  REQUIRE(bad.error);
  CHECK(bad.error->kind == RunError::Kind::BadInput);
  CHECK_THAT(bad.error->message, Contains("unknown capture scheme"));
}

TEST_CASE("ingest.vlm with no box in any view fails, unless allow_empty says the graph means it") {
  const fs::path dir = capture_with_replies("ingest_nodes_no_box");
  std::ofstream(dir / "vlm/cam_01/round_0.txt", std::ios::trunc) << "[]";  // the VLM found nothing
  const auto graph = [&](const std::string& vlm_params) {
    Registry registry;
    register_ingest_nodes(registry);
    return run_graph_text(
        "graph: g\nnodes:\n  capture: {type: ingest.capture, params: {path: \"" + dir.string() +
            "\"}}\n  vlm: {type: ingest.vlm, in: {capture: capture.capture}" + vlm_params + "}\n",
        registry);
  };
  const RunResult empty = graph("");
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error->kind == RunError::Kind::BadInput);
  CHECK(empty.error->node == "vlm");
  CHECK_THAT(empty.error->message,
             Contains("ingest.vlm: no box in any of the 3 views of capture 'small' (0 replies did "
                      "not parse)") &&
                 Contains("allow_empty: true"));
  const RunResult allowed = graph(", params: {allow_empty: true}");
  INFO((allowed.error ? allowed.error->str() : std::string()));
  CHECK(allowed.ok());
}
