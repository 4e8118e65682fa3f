// A scripted `gslift segment` session on the hand-built feature scene: good prompts are answered
// with their selection, bad ones get an error line and the session goes on.
#include "nodes/inference/segment_session.hpp"

#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

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

namespace {

// The model and capture of the scripted session above, and a session over `text`.
struct OneViewScene {
  GaussianModel model = test::two_blobs();
  Capture capture;
  OneViewScene() {
    model.instance_ids.clear();
    model.feature_dim = 2;
    model.features = {1, 0, 0, 1};
    View v;
    v.name = "v0";
    v.camera = test::query_camera();
    capture.views.push_back(v);
  }
  std::vector<nlohmann::json> session(std::istream& in, int& answered) {
    std::ostringstream out;
    answered = run_segment_session(model, capture, {}, in, out);
    std::istringstream lines(out.str());
    std::vector<nlohmann::json> replies;
    for (std::string line; std::getline(lines, line);)
      replies.push_back(nlohmann::json::parse(line));
    return replies;
  }
};

}  // namespace

TEST_CASE("hostile prompt lines get an error reply and the session goes on") {
  OneViewScene scene;
  const auto dir = test::scratch_dir("segment_session_hostile");
  const std::string good = R"({"name": "left", "view": "v0", "positive": [[17, 24]]})";
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "{\"a\":";
  deep += "1" + std::string(100000, '}');
  const std::string named =
      R"(", "view": "v0", "positive": [[17, 24]], "output": ")" + dir.string() + "\"}";
  std::istringstream in(
      "{\"name\": \"caf\xe9\", \"view\": \"v0\"}\n" +  // Latin-1: not UTF-8
      deep + "\n" +                                    // issue 33: the session died here
      "{\"view\": \"v0\", \"name\": \"" + std::string(2 << 20, 'x') + "\"}\n" +  // over 1 MiB
      R"({"view": "v0", "positive": [[1e308, 0]]})" + "\n" + R"({"name": "/a/x/P)" + named + "\n" +
      R"({"name": "../../a/x/p)" + named + "\n" +  // the same files as "/a/x/P"
      R"({"name": "/a/x/P)" + named + "\n" +       // the same name again overwrites its own
      R"({"name": ")" + named + "\n" +             // "" and "." are both "query"
      R"({"name": ".)" + named + "\n" + good + "\n");
  int answered = 0;
  const auto replies = scene.session(in, answered);
  REQUIRE(replies.size() == 10);
  CHECK(answered == 4);
  const auto error = [&](size_t k) { return replies[k].value("error", std::string()); };
  CHECK(replies[0]["ok"] == false);
  CHECK(error(0).find("\\xE9") != std::string::npos);  // the byte, escaped
  CHECK(error(1).find("nested more than 256 levels") != std::string::npos);
  CHECK(error(2).find("the line is 2097178 bytes long, over the 1048576-byte limit") !=
        std::string::npos);
  CHECK(replies[2]["line"] == 3);
  CHECK(error(3).find("[1e+308,0], a pixel outside any image") != std::string::npos);
  CHECK(replies[4]["ok"] == true);
  CHECK(replies[5]["ok"] == false);
  CHECK(error(5).find("\"../../a/x/p\" writes the same files as \"/a/x/P\" (a_x_p)") !=
        std::string::npos);
  CHECK(replies[6]["ok"] == true);
  CHECK(replies[7]["ok"] == true);
  CHECK(replies[8]["ok"] == false);
  CHECK(error(8).find("\".\" writes the same files as \"\" (query)") != std::string::npos);
  CHECK(replies[9]["ok"] == true);
  CHECK(replies[9]["name"] == "left");
}

TEST_CASE("a read error on the prompts is an error, not the end of the session") {
  // A stream buffer that fails after its first line, as a disk or a pipe can.
  struct FailingBuffer : std::streambuf {
    std::string first = "{\"name\": \"left\", \"view\": \"v0\", \"positive\": [[17, 24]]}\n";
    bool served = false;
    int_type underflow() override {
      if (served) throw std::runtime_error("I/O error");
      served = true;
      setg(first.data(), first.data(), first.data() + first.size());
      return traits_type::to_int_type(first[0]);
    }
  } buffer;
  std::istream in(&buffer);
  OneViewScene scene;
  std::ostringstream out;
  CHECK_THROWS_WITH(run_segment_session(scene.model, scene.capture, {}, in, out),
                    "reading the prompts failed after line 1");
  CHECK(nlohmann::json::parse(out.str())["ok"] == true);
}
