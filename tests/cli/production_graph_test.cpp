// graphs/README.md's "bring your own capture" walk-through, run: a capture without ground truth
// (one `gslift synth` writes, its gt/ removed) checked, then segmented by production LangOR with
// the user's own text queries.
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "nodes/scene/image_io.hpp"
#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
namespace fs = std::filesystem;

namespace {
const std::string kBinary = GSLIFT_BINARY;
const std::string kGraphs = std::string(GSLIFT_SOURCE_DIR) + "/graphs/";

std::string sh_quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}
}  // namespace

TEST_CASE("production LangOR answers the user's own queries on a capture without ground truth",
          "[cli][production]") {
  const fs::path dir = test::scratch_dir("production_langor");
  const fs::path capture = dir / "capture";
  const auto synth = run_command(kBinary + " synth --out " + sh_quoted(capture) +
                                 " --width 160 --height 120 --log-level warn");
  INFO(synth.output);
  REQUIRE(synth.code == exit_code::kOk);
  fs::remove_all(capture / "gt");  // a capture of one's own has no ground truth

  // The evaluated graph is refused before it runs, naming what only ground truth gives.
  const auto evaluated = run_command(kBinary + " validate " + sh_quoted(kGraphs + "langor.yaml") +
                                     " --input " + sh_quoted(capture));
  INFO(evaluated.output);
  CHECK(evaluated.code == exit_code::kBadInput);
  CHECK(evaluated.output.find("node 'eval' (eval.langor) needs ground-truth class maps") !=
        std::string::npos);
  // So is the production graph without queries: they would be the ground-truth class names.
  const std::string production = sh_quoted(kGraphs + "production/langor.yaml");
  const auto no_queries =
      run_command(kBinary + " validate " + production + " --input " + sh_quoted(capture));
  INFO(no_queries.output);
  CHECK(no_queries.code == exit_code::kBadInput);
  CHECK(no_queries.output.find("node 'query' (inference.text_query) needs ground-truth class "
                               "names") != std::string::npos);

  const std::string queries = " --set 'query.queries=[operating table, nurse]'";
  const auto checked =
      run_command(kBinary + " validate " + production + " --input " + sh_quoted(capture) + queries);
  INFO(checked.output);
  REQUIRE(checked.code == exit_code::kOk);

  const fs::path out = dir / "out";
  const auto run =
      run_command(kBinary + " run " + production + " --input " + sh_quoted(capture) + " --out " +
                  sh_quoted(out) + queries + " --no-cache --threads 2 --log-level warn");
  INFO(run.output);
  REQUIRE(run.code == exit_code::kOk);
  CHECK_FALSE(fs::exists(out / "eval"));
  const fs::path query = out / "query";
  // segmented.ply holds Gaussians: more than its header.
  REQUIRE(fs::exists(query / "segmented.ply"));
  CHECK(fs::file_size(query / "segmented.ply") > 10000);
  std::ifstream in(query / "queries.json");
  const nlohmann::json answers = nlohmann::json::parse(in);
  REQUIRE(answers.size() == 2);
  CHECK(answers[0]["query"] == "operating table");
  CHECK(answers[1]["query"] == "nurse");
  // Each query selected an instance, and its mask covers pixels in some view (answered in every
  // view: no held-out view is needed).
  for (const auto& a : answers) {
    INFO(a.dump());
    CHECK_FALSE(a["instances"].empty());
    int views = 0, covered = 0;
    for (const auto& e : fs::directory_iterator(query)) {
      const std::string name = e.path().filename().string();
      if (name.find("__" + a["file_stem"].get<std::string>() + "_mask.png") == std::string::npos)
        continue;
      ++views;
      covered += cv::countNonZero(read_image(e.path(), cv::IMREAD_GRAYSCALE)) > 0;
    }
    CHECK(views == 5);
    CHECK(covered >= 1);
  }
}
