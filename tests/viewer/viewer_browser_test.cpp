// gslift view in a real browser (issue 32): Debian's Chromium, headless, driven over the DevTools
// protocol by tests/viewer/drive_viewer.mjs (node's standard library only, no npm package). A
// small LangOR run on the embedded OR is made first (the main job's graph with fewer steps), then
// the script loads its page, orbits, clicks the anesthesia machine in the first camera, moves the
// threshold slider, types the query "ventilator" (WordNet: the anesthesia machine), exports the
// selection and the view, and takes screenshots (kept in the build folder,
// tests/viewer/viewer_*.png). Skipped when chromium or node is not installed.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_skip.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::string browser_program() {
  for (const char* name : {"chromium", "chromium-browser"})
    if (run_command(std::string("command -v ") + name + " >/dev/null").code == 0) return name;
  return {};
}

}  // namespace

TEST_CASE("gslift view in headless Chromium: orbit, click, slider, query, export",
          "[viewer][browser]") {
  const std::string chromium = browser_program();
  const bool has_node = run_command("command -v node >/dev/null").code == 0;
  if (chromium.empty() || !has_node) {
    WARN("SKIPPED: " << (chromium.empty() ? "chromium" : "node")
                     << " is not installed (.ci/install installs both)");
    test::mark_skipped();
    return;
  }
  const std::string gslift = GSLIFT_BINARY;
  const fs::path dir = test::scratch_dir("viewer_browser");
  const fs::path run = dir / "run";
  // The main job's graph with fewer steps (the viewer's behaviour, not LangOR's accuracy, is
  // under test); the stage cache of this test's scratch folder only.
  const auto made =
      run_command(gslift + " run '" + GSLIFT_SOURCE_DIR + "/graphs/langor.yaml' --out '" +
                  run.string() + "' --cache-dir '" + (dir / "cache").string() +
                  "' --set recon.iterations=" GSLIFT_VIEWER_RECON_STEPS
                  " --set instfeat.iterations=150 --threads 2 --log-level warn");
  INFO(made.output);
  REQUIRE(made.code == exit_code::kOk);

  const fs::path shots = GSLIFT_SCREENSHOT_DIR;
  const auto driven =
      run_command("timeout 120 node '" + std::string(GSLIFT_SOURCE_DIR) +
                  "/tests/viewer/drive_viewer.mjs' --gslift '" + gslift + "' --run '" +
                  run.string() + "' --chromium " + chromium + " --out '" + shots.string() +
                  "' --class 'anesthesia machine' --query ventilator");
  INFO(driven.output);
  REQUIRE(driven.code == 0);
  const json r = json::parse(driven.output.substr(driven.output.rfind("\n{") + 1));
  INFO(r.dump(1));
  REQUIRE(r["ok"] == true);
  CHECK(r["page_errors"].empty());
  CHECK(r["console"].empty());
  CHECK(r["viewer_exit"] == 0);  // SIGINT stops it cleanly
  // The page: every camera, a legend row per instance, three pictures per held-out view.
  CHECK(r["info"]["views"] == 5);
  CHECK(r["info"]["legend"] == r["info"]["instances"]);
  CHECK(r["info"]["instances"].get<int>() >= 8);
  CHECK(r["info"]["heldout"] == 3);
  // Real content: an OR, not a blank or flat frame (luminance spread, thousands of colours).
  CHECK(r["start_canvas"]["std"].get<double>() > 20);
  CHECK(r["start_canvas"]["colours"].get<int>() > 500);
  // The drag orbited: new frames, and they differ from the first camera's.
  CHECK(r["orbit"]["frames"].get<int>() >= 1);
  CHECK(r["orbit"]["mean_abs_change"].get<double>() > 5);
  CHECK(r["orbit"]["canvas"]["std"].get<double>() > 20);
  // The click on the anesthesia machine selects it: IoU with its ground truth in that view.
  CHECK(r["click"]["selection"]["selected"].get<int>() > 100);
  CHECK(r["click"]["iou"].get<double>() > 0.5);
  // The slider: a higher threshold keeps fewer Gaussians; back at the page's 0.5, the click's
  // selection again.
  CHECK(r["slider"]["selected_at_095"].get<int>() < r["slider"]["selected_back"].get<int>());
  CHECK(r["slider"]["selected_back"] == r["click"]["selection"]["selected"]);
  // The typed query lands on the anesthesia machine and selects it.
  CHECK(r["query"]["selection"]["query_class"] == "anesthesia machine");
  CHECK(r["query"]["iou"].get<double>() > 0.5);
  // Exports: a PLY of at most the selected Gaussians (filtered), and the view as a PNG.
  CHECK(r["ply"]["status"] == 200);
  CHECK(r["ply"]["ply"] == true);
  CHECK(r["ply"]["vertices"].get<int>() > 100);
  CHECK(r["ply"]["vertices"].get<int>() <= r["query"]["selection"]["selected"].get<int>());
  CHECK(r["downloads"]["ply"].get<int>() > 10000);
  CHECK(r["downloads"]["png"].get<int>() > 50000);
  // Screenshots: a near-blank 640x480 PNG compresses to a few kilobytes.
  CHECK(r["screenshots"]["viewer_start.png"].get<int>() > 50000);
  CHECK(r["screenshots"]["viewer_click.png"].get<int>() > 50000);
  CHECK(r["screenshots"]["viewer_page.png"].get<int>() > 200000);
  WARN("screenshots in " << shots.string());
}
