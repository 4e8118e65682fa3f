// graphs/detector_fusion.yaml end to end on a small embedded operating room (320x240, shortened
// training), through the library as `gslift run` does. Measured at seed 0 (13:47 UTC
// 2026-11-24; the same records with 1 and 2 threads): CA 3D source 67.2, priors 78.5, fused 80.3,
// multi-view 89.8, smoothed 87.9; final GA 95.6, CP 80.9; about 16 s on the shared 2-core
// machine. The floors keep a wide margin: they
// catch a broken stage, not a small regression.
#include "nodes/builtin.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("detector fusion graph on a small embedded OR") {
  Registry registry;
  register_builtin_nodes(registry);
  LoadOptions load;
  load.vars["input"] = "embedded:or?seed=0&width=320&height=240";
  load.sets = {"recon.iterations=200", "instfeat.iterations=150"};
  const LoadResult g = load_graph(
      std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs/detector_fusion.yaml", registry, load);
  REQUIRE(g.ok());
  RunOptions options;
  options.out_dir = test::scratch_dir("detector_fusion_e2e");
  const RunResult run = execute(*g.graph, registry, options);
  INFO((run.error ? run.error->str() : std::string("ok")));
  REQUIRE(run.ok());
  auto metric = [&](const char* node, const char* key) {
    return std::get<double>(run.node(node)->records.at(key));
  };
  WARN("CA: 3D " << metric("eval_source3d", "CA") << ", priors " << metric("eval_priors", "CA")
                 << ", fused " << metric("eval_fused", "CA") << ", multi-view "
                 << metric("eval_multiview", "CA") << ", smoothed " << metric("semantic", "CA")
                 << "; GA " << metric("semantic", "GA") << ", CP " << metric("semantic", "CP"));
  CHECK(metric("semantic", "GA") >= 70);
  CHECK(metric("semantic", "CA") >= 50);
  CHECK(metric("semantic", "test/CA") >= 30);
  CHECK(std::get<double>(run.node("priors")->records.at("painted")) >= 20);
  CHECK(std::filesystem::exists(options.out_dir / "semantic/confusion.csv"));
  CHECK(std::filesystem::exists(options.out_dir / "semantic/confusion.png"));
  CHECK(std::filesystem::exists(options.out_dir / "semantic/classes.csv"));
}
