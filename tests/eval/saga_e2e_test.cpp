// graphs/saga.yaml and graphs/saga_dtu.yaml end to end at reduced settings (small images, short
// training), through the library as `gslift run` does. The floors sit well below the measured
// values (in each case's comment): they catch a broken stage, not a small regression.
#include "nodes/builtin.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

RunResult run_graph(const char* graph, const std::map<std::string, std::string>& vars,
                    const std::vector<std::string>& sets, const std::filesystem::path& out,
                    Registry& registry) {
  LoadOptions load;
  load.vars = vars;
  load.sets = sets;
  const LoadResult g =
      load_graph(std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs" / graph, registry, load);
  REQUIRE(g.ok());
  RunOptions options;
  options.out_dir = out;
  return execute(*g.graph, registry, options);
}

}  // namespace

TEST_CASE("saga graph on a small embedded OR reaches its accuracy floor") {
  Registry registry;
  register_builtin_nodes(registry);
  const auto out = test::scratch_dir("saga_e2e");
  const RunResult run =
      run_graph("saga.yaml", {{"input", "embedded:or?seed=0&width=320&height=240"}},
                {"recon.iterations=200", "affinity.iterations=300"}, out, registry);
  INFO((run.error ? run.error->str() : std::string("ok")));
  REQUIRE(run.ok());
  const auto& records = run.node("eval")->records;
  const double miou = std::get<double>(records.at("mIoU"));
  WARN("saga small OR: mIoU " << miou << " mAcc " << std::get<double>(records.at("mAcc")));
  CHECK(std::get<double>(records.at("prompts")) >= 8);
  CHECK(miou >= 15);
  CHECK(std::filesystem::exists(out / "render/scene_selection.ply"));
  CHECK(std::filesystem::exists(out / "affinity/model.ply"));
  CHECK(std::filesystem::exists(out / "eval/metrics.csv"));
}

TEST_CASE("saga on DTU scan 24 at 1/16 scale reaches its accuracy floor") {
  GSLIFT_REQUIRE_SHARED_DATA("dtu_scan24/sparse/0");
  Registry registry;
  register_builtin_nodes(registry);
  const auto out = test::scratch_dir("saga_dtu_e2e");
  const RunResult run = run_graph(
      "saga_dtu.yaml", {{"input", test::shared_data("dtu_scan24").string()}},
      {"capture.downscale=16", "recon.iterations=150", "affinity.iterations=200"}, out, registry);
  INFO((run.error ? run.error->str() : std::string("ok")));
  REQUIRE(run.ok());
  const auto& records = run.node("eval")->records;
  const double miou = std::get<double>(records.at("mIoU"));
  WARN("saga DTU 1/16: mIoU " << miou << " mAcc " << std::get<double>(records.at("mAcc")));
  CHECK(std::get<double>(records.at("target_views")) == 24);
  CHECK(miou >= 50);
}
