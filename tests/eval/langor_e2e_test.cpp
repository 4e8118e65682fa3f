// graphs/langor.yaml end to end on a small embedded operating room (320x240, 200 reconstruction
// and 150 feature steps), through the library as `gslift run` does. The floors catch a broken
// stage, not a small regression (bench/ and the five-seed sweeps in docs/langor.md measure those).
//
// Why the floors sit where they do: at this length the run is chaotic. Rounding alone moves it: the
// same seed and graph gave mIoU / mLocAcc / mAcc 39.8 / 81.8 / 44.8 in the Release build (-O3
// -march=native) and 30.1 / 81.8 / 33.1 in CI's AddressSanitizer build (-O1, other float sums; 31.1
// / 81.8 / 34.3 in the same build on another host), and eight runs with one param nudged by 1e-6
// relative (recon.scale_weight, depth_weight, normal_weight each way, instfeat.lambda, lift.sigma)
// spread mIoU over 32.9-42.4 and mAcc over 35.8-47.8 (2026-11-27). Over those nine runs mIoU is
// 38.5 +- 4.2 and mAcc 43.3 +- 5.2, so the floors are about 3.4 standard deviations below the mean;
// mLocAcc never went under 72.7. A broken stage lands far below them: features trained 1 step give
// 1.0 / 18.2 / 1.0, a reconstruction of 20 steps 0.5 / 45.5 / 0.5. (Earlier floors of 30 / 50 / 35
// sat 2 deviations down and failed the sanitizer build once prune_hidden moved the mean from 48 to
// 40.) With the free-space tests at ray depth (langor.yaml of 2026-11-28): 35.9 / 81.8 / 40.7
// Release, 42.3 / 81.8 / 48.7 in the sanitizer build on this host.
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
  CHECK(miou >= 24);
  CHECK(locacc >= 50);
  CHECK(macc >= 26);
  CHECK(std::filesystem::exists(options.out_dir / "query/segmented.ply"));
  CHECK(std::filesystem::exists(options.out_dir / "eval/metrics.csv"));
}
