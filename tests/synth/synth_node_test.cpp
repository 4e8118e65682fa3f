// The synth.capture node through the executor, and its agreement with embedded: specs.
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "nodes/ingest/register.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/synth/register.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

TEST_CASE("synth.capture generates, caches and opens the capture its params describe") {
  const fs::path cache = test::scratch_dir("synth_node_cache");
  ::setenv("GSLIFT_CACHE", cache.c_str(), 1);
  Registry registry;
  register_ingest_nodes(registry);
  register_synth_nodes(registry);
  const RunResult r = run_graph_text(R"(
graph: synth
nodes:
  cap: {type: synth.capture, params: {seed: 1, views: 4, width: 64, height: 48, preset: hard,
                                      vlm_miss_rate: 0.5}}
  vlm: {type: ingest.vlm, in: {capture: cap.capture}}
  same: {type: ingest.capture,
         params: {path: "embedded:or?seed=1&views=4&width=64&height=48&preset=hard&vlm_miss_rate=0.5"}}
)",
                                     registry);
  ::unsetenv("GSLIFT_CACHE");
  INFO((r.error ? r.error->str() : std::string()));
  REQUIRE(r.ok());
  const auto capture = r.values.at("cap.capture").get<Capture>();
  REQUIRE(capture->views.size() == 4);
  CHECK(capture->test_views() == std::vector<int>{3});
  CHECK(capture->classes.size() == 12);
  // The node and the embedded: spec name the same settings, hence the same cached folder.
  CHECK(r.values.at("same.capture").get<Capture>()->root == capture->root);
  CHECK(capture->root.parent_path() == cache / "embedded");

  // The preset fills the knobs that were not set; the explicit one wins.
  std::ifstream f(capture->root / "synth.yaml");
  std::stringstream text;
  text << f.rdbuf();
  CHECK(text.str().find("vlm_miss_rate: 0.5\n") != std::string::npos);
  CHECK(text.str().find("depth_noise: 0.05\n") != std::string::npos);

  const auto boxes = r.values.at("vlm.boxes").get<BoxSet>();
  REQUIRE(boxes->views.size() == 4);
  CHECK(boxes->views[0].rounds == 5);
}
