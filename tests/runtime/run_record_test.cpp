#include <fstream>

#include <nlohmann/json.hpp>

#include "runtime/executor.hpp"
#include "runtime/run_record.hpp"
#include "runtime/version.hpp"
#include "tests/json_file.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::debug_node;
using nlohmann::json;
namespace fs = std::filesystem;
using gslift::test::read_json;

TEST_CASE("run.json records the resolved graph, the run and every node", "[run_record]") {
  const Registry reg = test::debug_registry();
  Graph g;
  g.name = "demo";
  g.files = {"graphs/demo.yaml"};
  g.params = {{"seed", int64_t{3}}, {"input", std::string("embedded:or")}};
  g.nodes = {
      debug_node(reg, "c", "debug.constant", {}, {{"value", 1.5}}, 4),
      debug_node(reg, "r", "debug.random", {}, {}, 5),
      debug_node(reg, "sum", "debug.add", {{"a", {"c", "out"}}, {"b", {"r", "out"}}}, {}, 6)};
  const fs::path out = test::scratch_dir("run_record_ok");
  RunOptions opt;
  opt.out_dir = out;
  opt.seed = 3;
  opt.threads = 2;
  const RunResult r = execute(g, reg, opt);
  REQUIRE(r.ok());
  const json j = read_json(out / "run.json");

  CHECK(j["gslift"]["version"] == gslift_version());
  CHECK(j["gslift"]["git"] == gslift_git_version());
  CHECK(j["graph"]["name"] == "demo");
  CHECK(j["graph"]["files"] == json::array({"graphs/demo.yaml"}));
  CHECK(j["graph"]["params"]["seed"] == 3);
  CHECK(j["graph"]["params"]["input"] == "embedded:or");
  REQUIRE(j["graph"]["nodes"].size() == 3);
  const json& sum = j["graph"]["nodes"][2];
  CHECK(sum["id"] == "sum");
  CHECK(sum["type"] == "debug.add");
  CHECK(sum["loc"] == "test.yaml:6:3");
  CHECK(sum["inputs"]["a"] == "c.out");
  CHECK(sum["inputs"]["b"] == "r.out");
  CHECK(j["graph"]["nodes"][0]["params"]["value"] == 1.5);

  CHECK(j["run"]["status"] == "ok");
  CHECK(j["run"]["error"].is_null());
  CHECK(j["run"]["seed"] == 3);
  CHECK(j["run"]["threads"] == 2);
  const std::string started = j["run"]["started_at"];
  CHECK(started.size() == 20);
  CHECK(started[10] == 'T');
  CHECK(started.back() == 'Z');
  CHECK(j["run"]["total_s"].get<double>() == Approx(r.total_s));
  CHECK(j["run"]["peak_rss_mb"].get<double>() == Approx(r.peak_rss_kb / 1024.0));
  CHECK(j["run"]["peak_rss_mb"].get<double>() > 1.0);

  REQUIRE(j["nodes"].size() == 3);
  const json& rn = j["nodes"][1];
  CHECK(rn["id"] == "r");
  CHECK(rn["status"] == "ok");
  CHECK(rn["wall_s"].get<double>() ==
        Approx(rn["end_s"].get<double>() - rn["start_s"].get<double>()));
  CHECK(rn["records"]["draw"].get<double>() == std::get<double>(r.node("r")->records.at("draw")));
  CHECK(rn["records"]["seed"] == std::get<std::string>(r.node("r")->records.at("seed")));
  CHECK(rn["peak_rss_mb"].get<double>() == Approx(r.node("r")->peak_rss_kb / 1024.0));
  CHECK(rn["peak_rss_mb"].get<double>() > 1.0);
  CHECK(rn["peak_rss_mb"].get<double>() <= j["run"]["peak_rss_mb"].get<double>());
  CHECK_FALSE(rn.contains("error"));
}

TEST_CASE("run.json is written for a failed run too, with the error", "[run_record]") {
  const Registry reg = test::debug_registry();
  Graph g;
  g.name = "broken";
  g.nodes = {debug_node(reg, "c", "debug.constant", {}, {}, 2),
             debug_node(reg, "f", "debug.fail", {{"in", {"c", "out"}}},
                        {{"message", std::string("bad weights")}}, 3),
             debug_node(reg, "d", "debug.sleep", {{"in", {"f", "out"}}}, {}, 4)};
  const fs::path out = test::scratch_dir("run_record_failed");
  RunOptions opt;
  opt.out_dir = out;
  const RunResult r = execute(g, reg, opt);
  REQUIRE(r.status == RunStatus::Failed);
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["status"] == "failed");
  CHECK(j["run"]["error"]["kind"] == "node-failed");
  CHECK(j["run"]["error"]["node"] == "f");
  CHECK(j["run"]["error"]["type"] == "debug.fail");
  CHECK(j["run"]["error"]["loc"] == "test.yaml:3:3");
  CHECK(j["run"]["error"]["message"] == "bad weights");
  CHECK(j["nodes"][1]["status"] == "failed");
  CHECK(j["nodes"][1]["error"] == "bad weights");
  CHECK(j["nodes"][2]["status"] == "pending");
}

TEST_CASE("param values keep their JSON types", "[run_record]") {
  CHECK(param_json(int64_t{4}) == json(4));
  CHECK(param_json(0.25) == json(0.25));
  CHECK(param_json(true) == json(true));
  CHECK(param_json(std::string("sam")) == json("sam"));
  CHECK(param_json(std::vector<int64_t>{1, 2}) == json::array({1, 2}));
  CHECK(param_json(std::vector<std::string>{"a"}) == json::array({"a"}));
}
