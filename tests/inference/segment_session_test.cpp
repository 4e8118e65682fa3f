// A scripted `gslift segment` session on the hand-built feature scene: good prompts are answered
// with their selection, bad ones get an error line and the session goes on.
#include "nodes/inference/segment_session.hpp"

#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("a scripted segment session") {
  GaussianModel model = test::two_blobs();
  model.instance_ids.clear();
  model.feature_dim = 2;
  model.features = {1, 0, 0, 1};  // left blob e1, right blob e2
  Capture capture;
  View v;
  v.name = "v0";
  v.camera = test::query_camera();
  capture.views.push_back(v);
  const auto dir = test::scratch_dir("segment_session");
  std::istringstream in(
      R"({"name": "left", "view": "v0", "positive": [[17, 24]], "output": ")" + dir.string() +
      R"(", "ply": true})"
      "\n"
      R"({"name": "right", "view": "v0", "positive": [[47, 24]], "filter": true})"
      "\n\n"
      R"({"view": "v9", "positive": [[1, 1]]})"
      "\n"
      R"({"view": "v0", "positive": [[80, 1]]})"
      "\n"
      R"({"view": "v0", "kind": "mask", "mask": "missing.png"})"
      "\n"
      "not json\n"
      R"({"name": "left again", "view": "v0", "positive": [[17, 24]], "views": "all"})"
      "\n");
  std::ostringstream out;
  CHECK(run_segment_session(model, capture, {}, in, out) == 3);
  std::istringstream lines(out.str());
  std::vector<nlohmann::json> replies;
  for (std::string line; std::getline(lines, line);) replies.push_back(nlohmann::json::parse(line));
  REQUIRE(replies.size() == 7);
  CHECK(replies[0]["ok"] == true);
  CHECK(replies[0]["name"] == "left");
  CHECK(replies[0]["selected"] == 1);
  CHECK(replies[0]["views"] == nlohmann::json::array({"v0"}));
  CHECK(replies[0]["latency_ms"].get<double>() >= 0);
  CHECK(std::filesystem::exists(dir / "v0__left_mask.png"));
  CHECK(std::filesystem::exists(dir / "left.ply"));
  CHECK(std::filesystem::exists(dir / "scene_selection.ply"));
  CHECK(replies[1]["ok"] == true);
  CHECK(replies[1]["selected"] == 1);
  for (int k = 2; k < 6; ++k) {  // unknown view, pixel outside, unreadable mask, not JSON
    CHECK(replies[k]["ok"] == false);
    CHECK(!replies[k]["error"].get<std::string>().empty());
  }
  CHECK(replies[2]["line"] == 4);  // the blank line 3 is skipped, not answered
  CHECK(replies[2]["error"].get<std::string>().find("no view 'v9'") != std::string::npos);
  CHECK(replies[3]["error"].get<std::string>().find("outside") != std::string::npos);
  CHECK(replies[6]["ok"] == true);
}
