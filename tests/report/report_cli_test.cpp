// `gslift report` and `gslift diff` through the real command line, on fixtures and on run.json
// files that the runtime itself wrote (so that the reader follows the writer).
#include <fstream>

#include <nlohmann/json.hpp>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
namespace fs = std::filesystem;

namespace {

const std::string kBinary = GSLIFT_DEBUG_BINARY;

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("report and diff are listed in the help with their exit codes", "[report][cli]") {
  const auto help = run_command(kBinary + " --help");
  CHECK(help.output.find("  report ") != std::string::npos);
  CHECK(help.output.find("  diff ") != std::string::npos);
  CHECK(help.output.find("1    diff: the runs differ") != std::string::npos);
  for (const char* cmd : {"report", "diff"}) {
    const auto r = run_command(kBinary + " " + cmd + " --help");
    INFO(r.output);
    CHECK(r.code == exit_code::kOk);
    CHECK(r.output.find(std::string("usage: gslift ") + cmd) != std::string::npos);
  }
}

TEST_CASE("gslift report writes the page and says what it embedded", "[report][cli]") {
  const fs::path dir = test::scratch_dir("report_cli_run") / "run";
  fs::copy(test::test_data("report/run"), dir, fs::copy_options::recursive);
  const auto r = run_command(kBinary + " report " + quoted(dir));
  INFO(r.output);
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.find("report: " + (dir / "report.html").string() +
                      " (2 pictures embedded, 0 skipped)") != std::string::npos);
  CHECK(fs::file_size(dir / "report.html") > 5000);
  const auto capped = run_command(kBinary + " report " + quoted(dir) + " --max-picture-mb 0");
  CHECK(capped.output.find("(0 pictures embedded, 2 skipped)") != std::string::npos);

  const fs::path sweep = test::scratch_dir("report_cli_sweep") / "sweep";
  fs::copy(test::test_data("report/sweep"), sweep, fs::copy_options::recursive);
  const auto s = run_command(kBinary + " report " + quoted(sweep));
  INFO(s.output);
  CHECK(s.code == exit_code::kOk);
  CHECK(s.output.find("report: " + (sweep / "report.html").string() +
                      " (and 7 run reports, their 14 pictures linked)") != std::string::npos);
}

TEST_CASE("report and diff on bad folders exit 4 naming the path and usage errors exit 2",
          "[report][cli]") {
  const fs::path dir = test::scratch_dir("report_cli_bad");
  const auto missing = run_command(kBinary + " report " + quoted(dir / "nope"));
  CHECK(missing.code == exit_code::kBadInput);
  CHECK(missing.output.find((dir / "nope").string()) != std::string::npos);
  const auto empty = run_command(kBinary + " report " + quoted(dir));
  CHECK(empty.code == exit_code::kBadInput);
  CHECK(empty.output.find((dir / "run.json").string()) != std::string::npos);
  std::ofstream(dir / "run.json") << "{ broken";
  const auto broken =
      run_command(kBinary + " diff " + quoted(dir) + " " + quoted(test::test_data("report/run")));
  CHECK(broken.code == exit_code::kBadInput);
  CHECK(broken.output.find((dir / "run.json").string() + " is not valid JSON") !=
        std::string::npos);
  CHECK(run_command(kBinary + " diff " + quoted(dir)).code == exit_code::kUsage);
  CHECK(run_command(kBinary + " report").code == exit_code::kUsage);
  CHECK(run_command(kBinary + " report x --max-picture-mb -1").code == exit_code::kUsage);
}

TEST_CASE("diff of two real runs: exit 1 with the changed param and record, 0 when the same",
          "[report][cli]") {
  const fs::path dir = test::scratch_dir("report_cli_diff");
  std::ofstream(dir / "sums.yaml") << "graph: sums\nparams: {seed: 1}\nnodes:\n"
                                      "  a: {type: debug.constant, params: {value: 1.5}}\n"
                                      "  r: {type: debug.random}\n"
                                      "  s: {type: debug.add, in: {a: a.out, b: r.out}}\n";
  const std::string run = kBinary + " run " + quoted(dir / "sums.yaml") + " --log-level off";
  REQUIRE(run_command(run + " --out " + quoted(dir / "one")).code == exit_code::kOk);
  REQUIRE(run_command(run + " --out " + quoted(dir / "two") + " --set a.value=3 --seed 7").code ==
          exit_code::kOk);
  REQUIRE(run_command(run + " --out " + quoted(dir / "same")).code == exit_code::kOk);

  const auto d = run_command(kBinary + " diff " + quoted(dir / "one") + " " + quoted(dir / "two"));
  INFO(d.output);
  CHECK(d.code == exit_code::kRunsDiffer);
  CHECK(d.output.find("  a.value: 1.5 -> 3 (+1.5, +100.00%)\n") != std::string::npos);
  CHECK(d.output.find("graph:\n  graph param seed: 1 -> 7 (+6, +600.00%)\n") != std::string::npos);
  CHECK(d.output.find("records:\n  r.draw: ") != std::string::npos);
  const auto same =
      run_command(kBinary + " diff " + quoted(dir / "one") + " " + quoted(dir / "same"));
  INFO(same.output);
  CHECK(same.code == exit_code::kOk);
  CHECK(same.output.find("no differences beyond time and memory") != std::string::npos);

  // The report reads what the runtime wrote.
  const auto r = run_command(kBinary + " report " + quoted(dir / "two"));
  CHECK(r.code == exit_code::kOk);
  const std::string html = read_text(dir / "two" / "report.html");
  CHECK(html.find("<title>s (debug.add)") != std::string::npos);
}

TEST_CASE("diff prints what a run.json holds capped and with its escapes escaped",
          "[report][cli]") {
  // Issue 33: diff's output passed terminal escape sequences from run.json through raw.
  const fs::path dir = test::scratch_dir("report_cli_diff_escapes");
  std::ofstream(dir / "one.yaml") << "graph: one\nnodes:\n"
                                     "  a: {type: debug.constant, params: {value: 1.5}}\n";
  REQUIRE(run_command(kBinary + " run " + quoted(dir / "one.yaml") + " --log-level off --out " +
                      quoted(dir / "one"))
              .code == exit_code::kOk);
  fs::copy(dir / "one", dir / "two", fs::copy_options::recursive);
  nlohmann::json j = nlohmann::json::parse(read_text(dir / "two" / "run.json"));
  j["graph"]["nodes"][0]["params"]["value"] = "\x1b]0;pwned\x07" + std::string(1000000, 'v');
  j["graph"]["name"] = "\x1b[2Jname";
  std::ofstream(dir / "two" / "run.json") << j.dump();
  const auto d = run_command(kBinary + " diff " + quoted(dir / "one") + " " + quoted(dir / "two"));
  INFO(d.output.substr(0, 2000));
  CHECK(d.code == exit_code::kRunsDiffer);
  CHECK(d.output.size() < 4000);
  CHECK(d.output.find_first_of("\x1b\x07") == std::string::npos);
  CHECK(d.output.find("a.value: 1.5 -> \\x1B]0;pwned\\x07vvv") != std::string::npos);
  CHECK(d.output.find("\\x1B[2Jname") != std::string::npos);
}
