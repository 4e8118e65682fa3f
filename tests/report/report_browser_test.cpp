// The report pages in a real browser (issue 15): Debian's Chromium, headless, loads each page
// with no console message and no failed resource, every picture decodes to a non-zero size,
// every chart is an SVG with a non-empty box and content, and a screenshot is taken (kept in the
// build folder, tests/report/report_*.png, to look at). Skipped when Chromium is not installed.
//
// How: a copy of the page gets a first <script> in <head> that records 'error' events (script
// errors and resources that fail to load, captured before anything else runs) and, on 'load',
// writes its findings as JSON into <pre id="gslift-check">, which --dump-dom prints. Chromium's
// own log (--enable-logging=stderr) shows every console message as "CONSOLE"; there must be none.
#include <fstream>

#include <nlohmann/json.hpp>

#include "report/html.hpp"
#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kBinary = GSLIFT_DEBUG_BINARY;

const char* kCheckScript = R"(<script>
window.gsliftErrors = [];
window.addEventListener('error', function (e) {
  var what = e.message || (e.target && (e.target.src || e.target.href)) || 'unknown';
  window.gsliftErrors.push(String(what).slice(0, 200));
}, true);
window.addEventListener('load', function () {
  var r = {images: 0, broken: [], charts: 0, empty: [], errors: window.gsliftErrors};
  document.querySelectorAll('img').forEach(function (img) {
    r.images++;
    if (!img.complete || img.naturalWidth === 0 || img.naturalHeight === 0) r.broken.push(img.alt);
  });
  document.querySelectorAll('figure.chart').forEach(function (f) {
    r.charts++;
    var svg = f.querySelector('svg');
    var box = svg ? svg.getBoundingClientRect() : {width: 0, height: 0};
    if (!svg || box.width < 50 || box.height < 30 || svg.querySelectorAll('text, rect, path, circle, line, polyline').length < 5)
      r.empty.push(f.id);
  });
  var pre = document.createElement('pre');
  pre.id = 'gslift-check';
  pre.textContent = JSON.stringify(r);
  document.body.appendChild(pre);
});
</script>
)";

std::string chromium() {
  for (const char* name : {"chromium", "chromium-browser"})
    if (run_command(std::string("command -v ") + name + " >/dev/null").code == 0) return name;
  return {};
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string unescape(std::string s) {
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"},
                                 {"&gt;", ">"},
                                 {"&quot;", "\""},
                                 {"&amp;", "&"}})
    for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + 1))
      s.replace(at, from.size(), to);
  return s;
}

// Flags every run needs: no GPU, no sandbox (CI runs as root), its own profile folder.
std::string browser(const std::string& exe, const fs::path& profile) {
  return "timeout 120 " + exe +
         " --headless --disable-gpu --no-sandbox --disable-dev-shm-usage --no-first-run "
         "--user-data-dir='" +
         profile.string() + "'";
}

// Loads `page` with the check script, requires a clean load with `images` pictures and `charts`
// charts, then takes a screenshot into the build folder.
void check_in_browser(const std::string& exe, const fs::path& page, size_t images, size_t charts,
                      const std::string& screenshot_name) {
  const fs::path work = page.parent_path();
  std::string html = read_text(page);
  const size_t head = html.find("<head>");
  REQUIRE(head != std::string::npos);
  html.insert(head + 6, std::string("\n") + kCheckScript);
  const fs::path checked = work / "report_checked.html";
  std::ofstream(checked, std::ios::binary) << html;

  const fs::path log = work / "chromium.log";
  const auto dom = run_command("(" + browser(exe, work / "profile") +
                               " --enable-logging=stderr --v=0 --virtual-time-budget=20000"
                               " --dump-dom 'file://" +
                               checked.string() + "' 2>'" + log.string() + "')");
  REQUIRE(dom.code == 0);
  const size_t begin = dom.output.find("<pre id=\"gslift-check\">");
  const size_t end = dom.output.find("</pre>", begin);
  INFO(dom.output.substr(0, 2000));
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  const json r = json::parse(unescape(dom.output.substr(begin + 23, end - begin - 23)));
  INFO(r.dump());
  CHECK(r["errors"].empty());
  CHECK(r["images"] == images);
  CHECK(r["broken"].empty());
  CHECK(r["charts"] == charts);
  CHECK(r["empty"].empty());
  // No console message at all (errors, warnings, logs).
  std::ifstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    INFO(line);
    CHECK(line.find("CONSOLE") == std::string::npos);
  }

  // The screenshot of the page itself (not the checked copy).
  const fs::path shot = fs::path(GSLIFT_SCREENSHOT_DIR) / screenshot_name;
  fs::remove(shot);
  const auto s = run_command(browser(exe, work / "profile") +
                             " --hide-scrollbars --window-size=1280,1600 --screenshot='" +
                             shot.string() + "' 'file://" + page.string() + "'");
  INFO(s.output);
  REQUIRE(fs::exists(shot));
  const std::string png = report::read_bytes(shot);
  const report::PixelSize size = report::picture_size(png);
  CHECK(size.width == 1280);
  CHECK(size.height == 1600);
  // A blank or near-blank page compresses to a few kilobytes.
  CHECK(png.size() > 30000);
  WARN("screenshot: " << shot.string());
}

}  // namespace

TEST_CASE("the run report loads cleanly in headless Chromium with its pictures and charts",
          "[report][browser]") {
  const std::string exe = chromium();
  if (exe.empty()) {
    WARN("SKIPPED: chromium is not installed (.ci/install installs it)");
    test::mark_skipped();
    return;
  }
  const fs::path dir = test::scratch_dir("report_browser_run") / "run";
  fs::copy(test::test_data("report/run"), dir, fs::copy_options::recursive);
  REQUIRE(run_command(kBinary + " report '" + dir.string() + "'").code == exit_code::kOk);
  check_in_browser(exe, dir / "report.html", 2, 2, "report_run.png");

  // The failed variant: the error box and the failed node's colour, same checks.
  const fs::path failed = test::scratch_dir("report_browser_failed") / "run_b";
  fs::copy(test::test_data("report/run_b"), failed, fs::copy_options::recursive);
  REQUIRE(run_command(kBinary + " report '" + failed.string() + "'").code == exit_code::kOk);
  check_in_browser(exe, failed / "report.html", 0, 2, "report_failed_run.png");
}

TEST_CASE("the sweep report loads cleanly in headless Chromium with every chart",
          "[report][browser]") {
  const std::string exe = chromium();
  if (exe.empty()) {
    WARN("SKIPPED: chromium is not installed (.ci/install installs it)");
    test::mark_skipped();
    return;
  }
  const fs::path dir = test::scratch_dir("report_browser_sweep") / "sweep";
  fs::copy(test::test_data("report/sweep"), dir, fs::copy_options::recursive);
  REQUIRE(run_command(kBinary + " report '" + dir.string() + "'").code == exit_code::kOk);
  check_in_browser(exe, dir / "report.html", 0, 4, "report_sweep.png");
  // A run's page in the sweep shows its pictures from the files beside it.
  check_in_browser(exe, dir / "runs/0000/report.html", 2, 2, "report_sweep_run.png");
}
