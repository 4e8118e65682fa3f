// graphs/langor.yaml end to end on a small embedded operating room (320x240, shortened training),
// through the library as `gslift run` does. Measured at seed 0: mIoU 50.8, mLocAcc 81.8, mAcc
// 63.5 (08:40 UTC 2026-11-22), then 43.3 / 72.7 / 49.9 after upstream stages changed defaults
// (09:05); about 12 s on a quiet 2-core machine. 14:10: 40.7 / 72.7 / 47.9 with label-aware box
// clustering and HDBSCAN min_samples 3 (the previous defaults give 44.2 / 81.8 / 51.4 at this
// reduced setting and seed; at the default setting the new ones gain 9.3 mIoU over seeds 0-4,
// docs/langor.md). 2026-11-25 with the line-of-sight prior (recon's second half and two-round
// pruning): 48.4 / 90.9 / 55.2 (38.2 / 90.9 / 44.6 with the pruning alone; 33.2 / 72.7 / 37.2
// with the loss from step 0). 2026-11-27 with prune_behind 0.8: the same 48.4 / 90.9 / 55.2 (seeds
// 1 and 2 moved 50.6 -> 41.5 and 40.4 -> 49.6: two Gaussians pruned at this length move the short
// run's mIoU by 9 points either way). Then with the line-of-sight passes vectorised (the same
// rules, float sums in another order): 41.8 / 90.9 / 48.3; prune_behind 0.7 with the loss at 0.8
// gave 30.6 / 81.8 / 33.9 and was not adopted. With edge_extent_weight 0.1: 48.2 / 90.9 / 54.4
// (seed 1: 38.6 -> 45.3 mIoU). With prune_hidden 0.9: 39.8 / 81.8 / 44.8. The floors keep a
// margin below the measurements:
// they catch a broken stage, not a small regression.
#include "nodes/builtin.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("langor graph on a small embedded OR reaches its accuracy floor") {
  Registry registry;
  register_builtin_nodes(registry);
  LoadOptions load;
  load.vars["input"] = "embedded:or?seed=0&width=320&height=240";
  load.sets = {"recon.iterations=200", "instfeat.iterations=150"};
  const LoadResult g =
      load_graph(std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs/langor.yaml", registry, load);
  REQUIRE(g.ok());
  RunOptions options;
  options.out_dir = test::scratch_dir("langor_e2e");
  const RunResult run = execute(*g.graph, registry, options);
  INFO((run.error ? run.error->str() : std::string("ok")));
  REQUIRE(run.ok());
  const auto& records = run.node("eval")->records;
  const double miou = std::get<double>(records.at("mIoU"));
  const double locacc = std::get<double>(records.at("mLocAcc"));
  const double macc = std::get<double>(records.at("mAcc"));
  WARN("mIoU " << miou << " mLocAcc " << locacc << " mAcc " << macc);
  CHECK(std::get<double>(records.at("queries")) >= 5);
  CHECK(miou >= 30);
  CHECK(locacc >= 50);
  CHECK(macc >= 35);
  CHECK(std::filesystem::exists(options.out_dir / "query/segmented.ply"));
  CHECK(std::filesystem::exists(options.out_dir / "eval/metrics.csv"));
}
