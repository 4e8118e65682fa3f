// The report opens with the results (issue 32): the headline metrics beside the README's floors,
// the per-class table of metrics.md and the ground truth | render | instances pictures, before
// the pipeline; a sweep's runs that came from the stage cache are marked, not shown as fast.
#include <fstream>

#include "report/floors.hpp"
#include "report/html.hpp"
#include "report/records.hpp"
#include "report/report_page.hpp"
#include "tests/json_file.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::report;
namespace fs = std::filesystem;

namespace {

// The fixture run (tests/data/report/run) made a LangOR run: its node "join" becomes the
// evaluation node "eval" of type eval.langor with LangOR's metrics, its metrics.md beside it and a
// side-by-side picture of a held-out view.
fs::path langor_like_run(const std::string& scratch) {
  const fs::path dir = test::scratch_dir(scratch) / "run";
  fs::copy(test::test_data("report/run"), dir, fs::copy_options::recursive);
  nlohmann::json j = test::read_json(dir / "run.json");
  j["graph"]["name"] = "langor";
  for (auto* list : {&j["graph"]["nodes"], &j["nodes"]})
    for (auto& n : *list)
      if (n["id"] == "join") {
        n["id"] = "eval";
        n["type"] = "eval.langor";
      }
  j["nodes"][3]["records"] = {{"queries", 12.0},           {"classes", 12.0},
                              {"mIoU", 65.59332420000666}, {"mLocAcc", 91.66666666666667},
                              {"mAcc", 69.81651241436687}, {"IoU/patient", 62.07}};
  std::ofstream(dir / "run.json") << j.dump(1);
  fs::rename(dir / "join", dir / "eval");
  std::ofstream(dir / "eval" / "metrics.md")
      << "| class | queries | IoU | LocAcc | LocAcc (box) | Acc |\n"
         "|---|---:|---:|---:|---:|---:|\n"
         "| patient | 1 | 62.07 | 100.00 | 100.00 | 62.48 |\n"
         "| mean over classes | 12 | 65.59 | 91.67 | 83.33 | 69.82 |\n";
  // Another picture's bytes and one more after its end (no decoder reads it), so that its
  // base64 appears nowhere else on the page.
  fs::copy_file(dir / "left" / "gradient.png", dir / "eval" / "cam_04_gt_render_instances.png");
  std::ofstream(dir / "eval" / "cam_04_gt_render_instances.png", std::ios::app) << '!';
  return dir;
}

std::string page_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("the run page opens with the results, then the held-out views, then the pipeline",
          "[report]") {
  const fs::path dir = langor_like_run("report_results_order");
  write_report(dir, ReportOptions{});
  const std::string html = page_of(dir / "report.html");
  const size_t results = html.find("<section id=\"results\">");
  const size_t classes = html.find("<h3 id=\"classes-eval\">");
  const size_t views = html.find("<h3 id=\"views\">");
  const size_t graph = html.find("<section id=\"graph\">");
  const size_t timeline = html.find("<section id=\"timeline\">");
  REQUIRE(results != std::string::npos);
  CHECK(results < classes);
  CHECK(classes < views);
  CHECK(views < graph);
  CHECK(graph < timeline);
  // The side-by-side picture is embedded once, under the results, not again among the pictures.
  const std::string picture = base64(read_bytes(dir / "eval/cam_04_gt_render_instances.png"));
  const size_t at = html.find(picture);
  CHECK(at > views);
  CHECK(at < graph);
  CHECK(html.find(picture, at + 1) == std::string::npos);
  // The per-class table as metrics.md has it, right-aligned where it says so.
  CHECK(html.find("<tr><td>patient</td><td class=\"num\">1</td><td class=\"num\">62.07</td>") !=
        std::string::npos);
  CHECK(html.find("<th>class</th><th class=\"num\">queries</th>") != std::string::npos);
}

TEST_CASE("the headline values on the page are those of the run's record, beside their floors",
          "[report]") {
  const fs::path dir = langor_like_run("report_results_values");
  write_report(dir, ReportOptions{});
  const std::string html = page_of(dir / "report.html");
  const nlohmann::json j = test::read_json(dir / "run.json");
  int shown = 0;
  for (const auto& [key, value] : j["nodes"][3]["records"].items()) {
    const std::string cell = "<td class=\"num headline-value\">" + number_text(value.get<double>());
    const bool headline = key == "mIoU" || key == "mLocAcc" || key == "mAcc";
    INFO(key);
    // Metrics are shown with their value; counts and per-class entries are not headlines.
    CHECK((html.find("<td><code>eval." + key + "</code></td>" + cell) != std::string::npos) ==
          headline);
    shown += headline;
  }
  CHECK(shown == 3);
  // 65.5933 against 70 is below, 91.6667 against 90 holds (floors.cpp, the README's floors).
  CHECK(html.find("65.5933</td><td class=\"num\">&ge; 70</td><td><span class=\"badge below\">") !=
        std::string::npos);
  CHECK(html.find("91.6667</td><td class=\"num\">&ge; 90</td><td><span class=\"badge holds\">") !=
        std::string::npos);
}

TEST_CASE("floors are found for the graph and its ablations only", "[report]") {
  REQUIRE(find_floor("langor", "eval.mIoU"));
  CHECK(find_floor("langor", "eval.mIoU")->floor == 70);
  CHECK(find_floor("langor_sigma_07", "eval.mAcc")->floor == 75);
  CHECK(find_floor("protosaga", "eval.mIoU")->floor == 55);
  CHECK(find_floor("gaga", "eval.mIoU") == nullptr);
  CHECK(find_floor("langorx", "eval.mIoU") == nullptr);
}

TEST_CASE("markdown_table_html keeps the cells and the alignment", "[report]") {
  CHECK(markdown_table_html("title\n| a | b |\n|---|--:|\n| x<y | 2 |\n") ==
        "<table class=\"markdown\">\n<tr><th>a</th><th class=\"num\">b</th></tr>\n"
        "<tr><td>x&lt;y</td><td class=\"num\">2</td></tr>\n</table>\n");
  CHECK(markdown_table_html("no table here").empty());
}

TEST_CASE("a sweep run loaded from the stage cache is marked cached, in its row and charts",
          "[report]") {
  const fs::path dir = test::scratch_dir("report_sweep_cached") / "sweep";
  fs::copy(test::test_data("report/sweep"), dir, fs::copy_options::recursive);
  // Only runs/0000 (grid point #1) loaded a node from the cache.
  for (int k = 1; k < 7; ++k) {
    const fs::path file = dir / ("runs/000" + std::to_string(k)) / "run.json";
    nlohmann::json j = test::read_json(file);
    for (auto& n : j["nodes"]) n["cache"] = "miss";
    std::ofstream(file) << j.dump(1);
  }
  write_report(dir, ReportOptions{});
  const std::string html = page_of(dir / "report.html");
  const size_t row = html.find("<code>runs/0000</code></a>");
  REQUIRE(row != std::string::npos);
  const size_t row_end = html.find("</tr>", row);
  CHECK(html.substr(row, row_end - row).find("badge cached\">cached</span>") != std::string::npos);
  CHECK(html.find("badge cached") == html.rfind("badge cached"));  // no other run
  // The time chart tags point #1 and says why; the memory chart does not.
  CHECK(html.find(">#1 cached<") != std::string::npos);
  CHECK(html.find(">#2 cached<") == std::string::npos);
  CHECK(html.find("their time is not the time to compute") != std::string::npos);
}
