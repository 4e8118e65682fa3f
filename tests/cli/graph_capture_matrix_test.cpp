// Every shipped graph (graphs/*.yaml, graphs/production/*.yaml) against every capture in
// ../shared/data, as `gslift validate GRAPH --input CAPTURE` checks it (the graph loaded with
// ${input}, then the preflight; no node runs): each cell either passes or is refused with one
// message per missing thing, naming the node and what it looked for. kMatrix is the expected
// outcome of every cell: the nodes whose needs the capture does not meet, "ok" for none.
#include <regex>
#include <set>

#include "graph/loader.hpp"
#include "nodes/builtin.hpp"
#include "runtime/preflight.hpp"
#include "runtime/registry.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

// The shared captures, in kMatrix's column order. The captures hold posed photos; Replica and
// 3DMatch also depth; none VLM replies, SAM masks or ground truth in gslift's layout; DTU's
// COLMAP model lists 49 cameras of which 25 have photos, so only graphs that set
// skip_missing_images (saga_dtu*) open it.
const std::vector<std::string> kCaptures = {"dtu_scan24",
                                            "nerf_synthetic_lego_subset",
                                            "instant_ngp_fox",
                                            "replica_nice_slam_rgbd/room0",
                                            "replica_nice_slam_rgbd/office0",
                                            "threedmatch_seq01_rgbd"};

struct MatrixRow {
  std::string graph;                 // under graphs/
  std::vector<std::string> sets;     // what a user must give (graph params declared null)
  std::vector<std::string> refused;  // per capture: the refusing nodes, '|'-separated, or "ok"
};

// "capture" = the capture cannot be opened (DTU: "image listed in the COLMAP model ... is
// missing (set skip_missing_images ...)"). saga_dtu*.yaml and saga_lego.yaml read their object
// masks with masks.folder (`truth`): DTU's mask/, the lego split's train/ RGBA images.
const std::vector<MatrixRow> kMatrix = {
    {"demo.yaml", {}, {"capture", "ok", "ok", "ok", "ok", "ok"}},
    {"detector_fusion.yaml",
     {},
     {"capture",
      "eval|eval_fused|eval_multiview|eval_priors|eval_source3d|multiview|priors|query|semantic|"
      "smooth|source3d|vlm",
      "eval|eval_fused|eval_multiview|eval_priors|eval_source3d|multiview|priors|query|semantic|"
      "smooth|source3d|vlm",
      "eval|eval_fused|eval_multiview|eval_priors|eval_source3d|priors|query|semantic|source3d|vlm",
      "eval|eval_fused|eval_multiview|eval_priors|eval_source3d|priors|query|semantic|source3d|vlm",
      "eval|eval_fused|eval_multiview|eval_priors|eval_source3d|priors|query|semantic|source3d|"
      "vlm"}},
    {"gaga.yaml",
     {},
     {"capture", "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam",
      "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam"}},
    {"langor.yaml",
     {},
     {"capture", "eval|query|vlm", "eval|query|vlm", "eval|query|vlm", "eval|query|vlm",
      "eval|query|vlm"}},
    {"protosaga.yaml",
     {},
     {"capture", "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam",
      "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam", "assoc_eval|eval|infer|sam"}},
    {"saga.yaml",
     {},
     {"capture", "render|sam|truth", "render|sam|truth", "render|sam|truth", "render|sam|truth",
      "render|sam|truth"}},
    {"saga_dtu.yaml", {}, {"ok", "truth", "truth", "truth", "truth", "truth"}},
    {"saga_dtu_test.yaml", {}, {"ok", "truth", "truth", "truth", "truth", "truth"}},
    {"saga_lego.yaml", {}, {"truth", "ok", "truth", "truth", "truth", "truth"}},
    {"production/detector_fusion.yaml",
     {"classes=[operating table, surgeon]"},
     {"capture", "multiview|smooth|vlm", "multiview|smooth|vlm", "vlm", "vlm", "vlm"}},
    {"production/gaga.yaml", {}, {"capture", "sam", "sam", "sam", "sam", "sam"}},
    {"production/langor.yaml",
     {},
     {"capture", "query|vlm", "query|vlm", "query|vlm", "query|vlm", "query|vlm"}},
    {"production/protosaga.yaml", {}, {"capture", "sam", "sam", "sam", "sam", "sam"}},
    {"production/saga.yaml",
     {"prompts=clicks.json"},
     {"capture", "sam", "sam", "sam", "sam", "sam"}},
};

std::string refusing_nodes(const std::vector<std::string>& problems) {
  static const std::regex node(": node '([^']+)' \\(");
  std::set<std::string> ids;
  for (const std::string& p : problems) {
    std::smatch m;
    if (std::regex_search(p, m, node)) ids.insert(m[1]);
  }
  std::string out;
  for (const std::string& id : ids) out += (out.empty() ? "" : "|") + id;
  return out.empty() ? "ok" : out;
}

}  // namespace

TEST_CASE("every shipped graph on every shared capture: passes, or refused naming what is missing",
          "[cli][preflight]") {
  for (const std::string& capture : kCaptures) GSLIFT_REQUIRE_SHARED_DATA(capture);
  Registry registry;
  register_builtin_nodes(registry);
  const fs::path graphs = fs::path(GSLIFT_SOURCE_DIR) / "graphs";

  // Every graph file shipped at the top level and in production/ has a row.
  std::set<std::string> shipped, listed;
  for (const char* dir : {"", "production/"})
    for (const auto& e : fs::directory_iterator(graphs / dir))
      if (e.path().extension() == ".yaml") shipped.insert(dir + e.path().filename().string());
  for (const MatrixRow& row : kMatrix) listed.insert(row.graph);
  CHECK(shipped == listed);

  for (const MatrixRow& row : kMatrix) {
    REQUIRE(row.refused.size() == kCaptures.size());
    for (size_t c = 0; c < kCaptures.size(); ++c) {
      INFO(row.graph << " on " << kCaptures[c]);
      LoadOptions options;
      options.vars["input"] = test::shared_data(kCaptures[c]).string();
      options.sets = row.sets;
      const LoadResult loaded = load_graph(graphs / row.graph, registry, options);
      std::string diagnostics;
      for (const auto& d : loaded.diagnostics) diagnostics += d.str() + "\n";
      INFO(diagnostics);
      REQUIRE(loaded.ok());
      const std::vector<std::string> problems = preflight_problems(*loaded.graph, registry);
      std::string all;
      for (const std::string& p : problems) all += p + "\n";
      INFO(all);
      CHECK(refusing_nodes(problems) == row.refused[c]);
      // Each message names what was looked for, or why the capture does not open.
      for (const std::string& p : problems)
        CHECK((p.find(": looked for ") != std::string::npos ||
               p.find("cannot open its capture: ") != std::string::npos));
      if (row.refused[c] == "capture") CHECK(all.find("skip_missing_images") != std::string::npos);
    }
  }
}
