// Reading run and sweep folders, and the HTML pages written from them (tests/data/report/: a
// 4-node run with two small PNGs and a text file, a failed variant of it, and a 2 x 2 x 2-seed
// sweep whose last run failed before writing run.json).
#include <fstream>
#include <regex>

#include "base/errors.hpp"
#include "report/html.hpp"
#include "report/records.hpp"
#include "report/report_page.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::report;
namespace fs = std::filesystem;

namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

fs::path copy_fixture(const std::string& name, const std::string& scratch) {
  const fs::path dir = test::scratch_dir(scratch) / name;
  fs::copy(test::test_data("report/" + name), dir, fs::copy_options::recursive);
  return dir;
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void check_input_error(const std::function<void()>& f, const std::string& mentions) {
  try {
    f();
    FAIL("no InputError");
  } catch (const InputError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find(mentions) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("read_run_record reads every field of run.json", "[report]") {
  const RunRecord r = read_run_record(test::test_data("report/run"));
  CHECK(r.graph_name == "tiny");
  CHECK(r.graph_files == std::vector<std::string>{"graphs/tiny.yaml"});
  CHECK(r.version == "0.1.0");
  CHECK(r.status == "ok");
  CHECK(r.error.empty());
  CHECK(r.threads == 2);
  CHECK(r.total_s == 2.6);
  CHECK(r.peak_rss_mb == 120.5);
  REQUIRE(r.graph.size() == 4);
  CHECK(r.graph[3].inputs.at("base") == "source.out");
  CHECK(r.graph[1].params.at("factor") == 2.0);
  REQUIRE(r.nodes.size() == 4);
  CHECK(r.node("left")->wall_s == 1.5);
  CHECK(r.node("left")->records.at("mode") == "fast");
  CHECK(r.node("source")->cache == "hit");
  CHECK(r.has_cache_column());

  const RunRecord b = read_run_record(test::test_data("report/run_b"));
  CHECK(b.status == "failed");
  CHECK(b.error ==
        "graphs/tiny.yaml:8:3: node 'extra' (debug.fail): boom: the debug node failed on purpose "
        "[node-failed]");
  CHECK(b.node("extra")->error == "boom: the debug node failed on purpose");
}

TEST_CASE("a folder that is not a readable run is bad input naming the path", "[report]") {
  const fs::path dir = test::scratch_dir("report_bad_input");
  check_input_error([&] { read_run_record(dir / "absent"); }, (dir / "absent").string());
  check_input_error([&] { read_run_record(dir); }, (dir / "run.json").string());
  std::ofstream(dir / "run.json") << "{\"graph\": {\"nodes\": [";
  check_input_error([&] { read_run_record(dir); }, "is not valid JSON");
  std::ofstream(dir / "run.json") << "{\"graph\": {\"nodes\": []}, \"nodes\": []}";
  check_input_error([&] { read_run_record(dir); }, "missing field 'gslift'");
  std::ofstream(dir / "run.json")
      << R"({"gslift": {}, "graph": {"nodes": []}, "run": {"status": "ok"},
             "nodes": [{"id": "a", "status": "ok", "start_s": "soon", "end_s": 1}]})";
  check_input_error([&] { read_run_record(dir); }, (dir / "run.json").string());
  check_input_error([&] { read_sweep_record(dir); }, (dir / "sweep.json").string());
}

TEST_CASE("a run.json param nested 100,000 levels deep is bad input, not a stack overflow",
          "[report]") {
  const fs::path dir = copy_fixture("run", "report_deep_param");
  std::string text = read_text(dir / "run.json");
  const std::string param = "\"factor\": 2.0";
  const auto at = text.find(param);
  REQUIRE(at != std::string::npos);
  text.replace(at, param.size(),
               "\"factor\": " + std::string(100000, '[') + "2" + std::string(100000, ']'));
  std::ofstream(dir / "run.json", std::ios::binary) << text;
  check_input_error([&] { read_run_record(dir); }, "nested more than 256 levels");
}

TEST_CASE("number_text and value_text print values as a person reads them", "[report]") {
  CHECK(number_text(57616.0) == "57616");
  CHECK(number_text(142140952.0) == "142140952");
  CHECK(number_text(56.499463167) == "56.4995");
  CHECK(number_text(-0.25) == "-0.25");
  CHECK(value_text(nlohmann::json("fast")) == "fast");
  CHECK(value_text(nlohmann::json(true)) == "true");
  CHECK(value_text(nlohmann::json::array({1, 2})) == "[1,2]");
}

TEST_CASE("base64 follows RFC 4648's test vectors", "[report]") {
  CHECK(base64("") == "");
  CHECK(base64("f") == "Zg==");
  CHECK(base64("fo") == "Zm8=");
  CHECK(base64("foo") == "Zm9v");
  CHECK(base64("foob") == "Zm9vYg==");
  CHECK(base64("fooba") == "Zm9vYmE=");
  CHECK(base64("foobar") == "Zm9vYmFy");
  CHECK(base64(std::string("\xff\x00\xfe", 3)) == "/wD+");
}

TEST_CASE("picture_size reads PNG and JPEG headers", "[report]") {
  const PixelSize png = picture_size(read_bytes(test::test_data("report/run/left/gradient.png")));
  CHECK(png.width == 32);
  CHECK(png.height == 24);
  // SOI, an APP0 segment of 4 bytes, then SOF0: length 17, precision 8, height 300, width 400.
  const std::string jpeg("\xFF\xD8\xFF\xE0\x00\x04\x00\x00\xFF\xC0\x00\x11\x08\x01\x2C\x01\x90\x03",
                         18);
  const PixelSize j = picture_size(jpeg);
  CHECK(j.width == 400);
  CHECK(j.height == 300);
  CHECK(picture_size("not a picture").width == 0);
  CHECK(picture_mime("a/B.PNG") == "image/png");
  CHECK(picture_mime("x.jpeg") == "image/jpeg");
  CHECK(picture_mime("model.ply").empty());
}

TEST_CASE("the run page has the graph, the timeline, the tables and every picture", "[report]") {
  const fs::path dir = copy_fixture("run", "report_run_page");
  ReportStats stats;
  const fs::path page = write_report(dir, ReportOptions{}, &stats);
  CHECK(page == dir / "report.html");
  CHECK(stats.pictures_embedded == 2);
  CHECK(stats.pictures_skipped == 0);
  const std::string html = read_text(page);
  REQUIRE(html.rfind("<!DOCTYPE html>", 0) == 0);
  // The diagram: a box per node (titled with its id), an edge per input (5 inputs).
  CHECK(count(html, "class='graph-node'") == 4);
  for (const char* id : {"source", "left", "right", "join"})
    CHECK(html.find("<title>" + std::string(id) + " (") != std::string::npos);
  CHECK(count(html, "class='graph-edge'") == 4 + 1);
  CHECK(html.find(">in</text>") == std::string::npos);  // "out→in": the ports differ
  CHECK(html.find("out\u2192in") != std::string::npos);
  // The timeline: a bar per node that ran; left [0.5, 2] and right [0.6, 1.6] overlap.
  CHECK(count(html, "class='timeline-bar'") == 4);
  CHECK(html.find("at most 2 nodes ran at once") != std::string::npos);
  // Tables: the cache column (present in this run.json), records, params.
  CHECK(html.find("<th>cache</th>") != std::string::npos);
  CHECK(html.find("<span class=\"badge hit\">hit</span>") != std::string::npos);
  CHECK(html.find("<td>mIoU</td><td class=\"num\">50</td>") != std::string::npos);
  CHECK(html.find("<td>mode</td><td class=\"num\">fast</td>") != std::string::npos);
  CHECK(html.find("<td class=\"num\">110 MB</td>") != std::string::npos);
  // The pictures as data URIs of the very bytes of the files, with their sizes; the text file
  // listed as another file.
  const std::string gradient = read_bytes(dir / "left/gradient.png");
  CHECK(html.find("src=\"data:image/png;base64," + base64(gradient) + "\"") != std::string::npos);
  CHECK(html.find("width=\"32\" height=\"24\"") != std::string::npos);
  CHECK(html.find("left/gradient.png</code></a> · 32×24") != std::string::npos);
  CHECK(html.find("width=\"16\" height=\"12\"") != std::string::npos);
  CHECK(html.find("join/values.txt") != std::string::npos);
  CHECK(html.find("report.html</code>") == std::string::npos);  // not listing itself
  // Self-contained: the only URL is the SVG namespace.
  CHECK(count(html, "http") == count(html, "xmlns='http://www.w3.org/2000/svg'") +
                                   count(html, "http-equiv=\"Content-Security-Policy\""));
  CHECK(html.find("<script") == std::string::npos);
  CHECK(html.find("class=\"error\"") == std::string::npos);

  // A second report replaces the first without listing it.
  write_report(dir, ReportOptions{});
  CHECK(read_text(page) == html);
}

TEST_CASE("pictures over the cap are listed, not embedded", "[report]") {
  const RunRecord run = read_run_record(test::test_data("report/run"));
  ReportOptions opt;
  opt.max_picture_bytes = 1000;  // gradient.png is 1474 bytes, mask.png 91
  ReportStats stats;
  const std::string html = run_report_html(run, opt, &stats);
  CHECK(stats.pictures_embedded == 1);
  CHECK(stats.pictures_skipped == 1);
  CHECK(count(html, "data:image/png;base64,") == 1);
  CHECK(html.find("1 more not embedded") != std::string::npos);
  CHECK(html.find("<li><a href=\"./left/gradient.png\">") != std::string::npos);
}

TEST_CASE("a failed run's page shows its error and the failed node", "[report]") {
  const RunRecord run = read_run_record(test::test_data("report/run_b"));
  const std::string html = run_report_html(run, ReportOptions{});
  CHECK(html.find("<span class=\"badge failed\">failed</span>") != std::string::npos);
  CHECK(html.find("<div class=\"error\">graphs/tiny.yaml:8:3: node &#39;extra&#39;") !=
        std::string::npos);
  CHECK(html.find("<tr class=\"failed\"><td><code>extra</code>") != std::string::npos);
  CHECK(count(html, "class='graph-node'") == 5);
  CHECK(count(html, "class='timeline-bar'") == 5);
}

TEST_CASE("sweep.json is read with its grid, runs and summary", "[report]") {
  const SweepRecord s = read_sweep_record(test::test_data("report/sweep"));
  CHECK(is_sweep_dir(test::test_data("report/sweep")));
  CHECK_FALSE(is_sweep_dir(test::test_data("report/run")));
  CHECK(s.graph == "graphs/tiny.yaml");
  CHECK(s.grid.at("left.factor") == std::vector<std::string>{"2", "3"});
  CHECK(s.seeds == std::vector<uint64_t>{0, 1});
  REQUIRE(s.runs.size() == 8);
  CHECK(s.runs[7].status == "failed");
  CHECK(s.runs[7].error == "debug.fail: boom");
  CHECK(std::isnan(s.runs[7].total_s));
  CHECK(s.runs[1].metrics.at("join.mIoU") == 56);
  REQUIRE(s.summary.size() == 4);
  CHECK(s.summary[0].metrics.at("join.mIoU").mean == 55.5);
  CHECK(s.summary[0].metrics.at("join.mIoU").std == Approx(std::sqrt(0.5)));
  CHECK(s.summary[3].failed == 1);
  CHECK(s.summary[3].n == 1);  // runs that succeeded
  CHECK(s.headline == std::vector<std::string>{"join.mIoU"});
}

TEST_CASE("the sweep page has the summary, the charts and a section per run", "[report]") {
  const fs::path dir = copy_fixture("sweep", "report_sweep_page");
  ReportStats stats;
  write_report(dir, ReportOptions{}, &stats);
  const std::string html = read_text(dir / "report.html");
  // Summary: mean ± std of group 0 (left 2, right 0.5): mIoU 55, 56; total 2.0, 2.2 s.
  CHECK(html.find("<td class=\"num\">55.5 ± 0.71</td>") != std::string::npos);
  CHECK(html.find("<td class=\"num\">2.1 ± 0.14 s</td>") != std::string::npos);
  // Charts for the headline metric join.mIoU: against time, memory, and both varied params.
  CHECK(count(html, "<figure class=\"chart\"") == 4);
  CHECK(count(html, "class='pareto-front'") == 2);
  // 4 grid points in each chart.
  CHECK(count(html, "class='chart-point'") == 4 * 4);
  // The other metric in the folded table of every metric, not in the summary's columns.
  CHECK(html.find("<th class=\"num\">left.sum</th>") == std::string::npos);
  CHECK(html.find("<tr><td>left.sum</td><td class=\"num\">12 ± 0</td>") != std::string::npos);
  // Runs: a row and a section each; the 7 runs with a record link to their own report, which
  // write_report wrote.
  CHECK(count(html, "<details id=\"run-") == 8);
  CHECK(count(html, "/report.html\">the run's own report</a>") == 7);
  CHECK(html.find("no run record: ") != std::string::npos);
  CHECK(html.find("debug.fail: boom") != std::string::npos);
  CHECK(stats.runs == 7);
  CHECK(stats.pictures_linked == 7 * 2);
  CHECK(stats.pictures_embedded == 0);
  for (int k = 0; k < 7; ++k) {
    // Each run's page shows its pictures from the files beside it, not embedded.
    const std::string run_page = read_text(dir / ("runs/000" + std::to_string(k)) / "report.html");
    CHECK(run_page.find("<img src=\"./left/gradient.png\"") != std::string::npos);
    CHECK(run_page.find("data:image") == std::string::npos);
  }
  CHECK(count(html, "http") == count(html, "xmlns='http://www.w3.org/2000/svg'") +
                                   count(html, "http-equiv=\"Content-Security-Policy\""));
}

TEST_CASE("a sweep without headline metrics charts every metric", "[report]") {
  SweepRecord s = read_sweep_record(test::test_data("report/sweep"));
  s.headline.clear();
  const std::string html = sweep_report_html(s);
  // 2 metrics x (time, memory, 2 varied params).
  CHECK(count(html, "<figure class=\"chart\"") == 8);
  CHECK(count(html, "class='pareto-front'") == 4);
  CHECK(html.find("<th class=\"num\">left.sum</th>") != std::string::npos);
  CHECK(html.find("id=\"all-metrics\"") == std::string::npos);
}

TEST_CASE("lower_is_better reads the metric's name", "[report]") {
  CHECK(lower_is_better("recon.loss_total"));
  CHECK(lower_is_better("recon.seconds"));
  CHECK(lower_is_better("bench.wall_s"));
  CHECK_FALSE(lower_is_better("eval.mIoU"));
  CHECK_FALSE(lower_is_better("recon.test_psnr"));
  CHECK_FALSE(lower_is_better("recon.gaussians"));
}

TEST_CASE("a sweep's run folders outside the sweep folder are refused", "[report]") {
  // gslift report writes report.html into each run's folder: sweep.json is data and may name any.
  const fs::path dir = copy_fixture("sweep", "report_sweep_outside");
  const std::string json = read_text(dir / "sweep.json");
  fs::create_directories(dir.parent_path() / "elsewhere");
  fs::create_directory_symlink(dir.parent_path() / "elsewhere", dir / "runs" / "link");
  for (const std::string& escape :
       {std::string("../elsewhere"), std::string("runs/../../elsewhere"),
        (dir.parent_path() / "elsewhere").string(), std::string("runs/link")}) {
    INFO(escape);
    std::string edited = json;
    const size_t at = edited.find("\"runs/0000\"");
    REQUIRE(at != std::string::npos);
    edited.replace(at, 11, "\"" + escape + "\"");
    std::ofstream(dir / "sweep.json") << edited;
    check_input_error([&] { write_report(dir, ReportOptions{}); },
                      "is not inside the sweep folder");
    CHECK_FALSE(fs::exists(dir.parent_path() / "elsewhere" / "report.html"));
  }
}

TEST_CASE("links are ./ and percent-encoded, and the page allows no script", "[report]") {
  const fs::path dir = copy_fixture("run", "report_run_links");
  fs::create_directories(dir / "left" / "javascript:alert(1)");
  std::ofstream(dir / "left" / "javascript:alert(1)" / "x.txt") << "x";
  write_report(dir, ReportOptions{});
  const std::string html = read_text(dir / "report.html");
  CHECK(html.find("href=\"./left/javascript%3Aalert%281%29/x.txt\"") != std::string::npos);
  CHECK(html.find("href=\"javascript") == std::string::npos);
  CHECK(html.find("<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none';") !=
        std::string::npos);
  CHECK(html.find("<script") == std::string::npos);
  CHECK(relative_href("a b/#c?.png") == "./a%20b/%23c%3F.png");
}
