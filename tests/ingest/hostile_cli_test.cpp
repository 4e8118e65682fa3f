// Hostile input through the gslift executable (issue 16): bytes that are not UTF-8, NUL bytes,
// YAML alias bombs, symlink loops, directories and FIFOs where files belong. Each case exits with
// the documented code and a message naming the file; none may crash, hang or lose run.json.
#include <sys/stat.h>

#include <chrono>
#include <fstream>

#include <nlohmann/json.hpp>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/ingest/small_capture.hpp"
#include "tests/json_file.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
using nlohmann::json;
namespace fs = std::filesystem;
using gslift::test::read_json;

namespace {

const std::string kBinary = GSLIFT_BINARY;

fs::path write_text(const fs::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

std::string shell_quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const std::string kDemo = std::string(GSLIFT_SOURCE_DIR) + "/graphs/demo.yaml";

}  // namespace

TEST_CASE("bytes that are not UTF-8 are recorded escaped, never lose run.json", "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_utf8");
  // A failing capture path in Latin-1: the real error (exit 4) and run.json with the path.
  const fs::path graph = write_text(dir / "latin.yaml",
                                    "graph: latin\nnodes:\n  capture: {type: ingest.capture, "
                                    "params: {path: \"/nonexistent/\xe9t\xe9\"}}\n");
  const auto r = run_command(kBinary + " run " + shell_quoted(graph) + " --out " +
                             shell_quoted(dir / "out") + " --log-level warn");
  INFO(r.output);
  CHECK(r.code == exit_code::kBadInput);
  CHECK(contains(r.output, "/nonexistent/\xe9t\xe9: no such capture folder"));
  REQUIRE(fs::exists(dir / "out/run.json"));
  const json j = read_json(dir / "out/run.json");
  CHECK(j["run"]["status"] == "failed");
  CHECK(j["graph"]["nodes"][0]["params"]["path"] == "/nonexistent/\\xE9t\\xE9");
  CHECK(contains(j["run"]["error"]["message"].get<std::string>(), "/nonexistent/\\xE9t\\xE9"));
}

TEST_CASE("a valid capture in a folder with a Latin-1 name runs", "[hostile]") {
  const fs::path capture = test::write_small_capture("caf\xe9", "");
  const fs::path out = test::scratch_dir("hostile_latin_out");
  const auto r =
      run_command(kBinary + " run " + shell_quoted(kDemo) + " --input " + shell_quoted(capture) +
                  " --out " + shell_quoted(out) + " --log-level warn");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["status"] == "ok");
  CHECK(contains(j["graph"]["params"]["input"].get<std::string>(), "/caf\\xE9"));
}

TEST_CASE("a NUL byte in a graph is an invalid graph naming the line", "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_nul");
  const fs::path graph =
      write_text(dir / "nul.yaml", "graph: \"a\\0b\"\nnodes:\n  capture: {type: ingest.capture}\n");
  const auto r = run_command(kBinary + " validate --print " + shell_quoted(graph));
  INFO(r.output);
  CHECK(r.code == exit_code::kInvalidGraph);
  CHECK(contains(r.output, graph.string() + ":1:8: error[schema]: a value may not contain a NUL"));
}

TEST_CASE("a YAML alias bomb in params is refused quickly, naming the line", "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_bomb");
  // 10 values, then 9 levels of 10 aliases each of the level below: 10^10 values expanded.
  std::string text = "graph: bomb\nparams:\n  l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level <= 9; ++level) {
    const std::string below = "*l" + std::to_string(level - 1);
    text += "  l" + std::to_string(level) + ": &l" + std::to_string(level) + " [";
    for (int k = 0; k < 10; ++k) text += (k ? ", " : "") + below;
    text += "]\n";
  }
  text += "nodes:\n  capture: {type: ingest.capture}\n";
  const fs::path graph = write_text(dir / "bomb.yaml", text);
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run_command(kBinary + " validate " + shell_quoted(graph));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(r.output);
  CHECK(r.code == exit_code::kInvalidGraph);
  CHECK(contains(r.output, graph.string() + ":"));
  CHECK(contains(r.output, "error[too-large]: the graph file expands to more than 100000 values"));
  // Not a speed measurement: a bound that only an unbounded expansion (minutes) can break.
  CHECK(seconds < 30);
}

TEST_CASE("symlink loops, directories and FIFOs as files are bad input naming them", "[hostile]") {
  const fs::path dir = test::scratch_dir("hostile_not_files");
  fs::create_symlink(dir / "loop_b.yaml", dir / "loop_a.yaml");
  fs::create_symlink(dir / "loop_a.yaml", dir / "loop_b.yaml");
  const auto loop = run_command(kBinary + " validate " + shell_quoted(dir / "loop_a.yaml"));
  CHECK(loop.code == exit_code::kBadInput);
  CHECK(contains(loop.output, (dir / "loop_a.yaml").string() + ": graph file is a symlink loop"));

  fs::create_directories(dir / "folder.yaml");
  const auto folder = run_command(kBinary + " validate " + shell_quoted(dir / "folder.yaml"));
  CHECK(folder.code == exit_code::kBadInput);
  CHECK(contains(folder.output,
                 (dir / "folder.yaml").string() + ": graph file is a directory, not a file"));

  REQUIRE(::mkfifo((dir / "fifo.yaml").c_str(), 0600) == 0);
  const auto fifo = run_command(kBinary + " validate " + shell_quoted(dir / "fifo.yaml"));
  CHECK(fifo.code == exit_code::kBadInput);
  CHECK(contains(fifo.output, (dir / "fifo.yaml").string() +
                                  ": graph file is not a regular file (a FIFO, socket or device)"));

  // A directory as the batch manifest: an error, not 0 captures and exit 0.
  fs::create_directories(dir / "manifest");
  const auto batch = run_command(kBinary + " batch " + shell_quoted(dir / "manifest") + " " +
                                 shell_quoted(kDemo) + " --out " + shell_quoted(dir / "batch_out"));
  CHECK(batch.code == exit_code::kBadInput);
  CHECK(contains(batch.output,
                 (dir / "manifest").string() + ": batch manifest is a directory, not a file"));

  // /dev/zero as the graph: refused at once, not read until memory runs out.
  const auto zero = run_command(kBinary + " validate /dev/zero");
  CHECK(zero.code == exit_code::kBadInput);
  CHECK(contains(zero.output, "/dev/zero: graph file is not a regular file"));
}

TEST_CASE("a capture.yaml value quoted in an error is capped and escaped", "[hostile]") {
  // Issue 33: a value went into the message whole (a megabyte of stderr and of run.json) and its
  // terminal escapes raw.
  const fs::path capture = test::write_small_capture(
      "hostile_coords", "vlm: {coords: \"\\e]0;pwned\\a" + std::string(1000000, 'x') + "\"}\n");
  const fs::path out = test::scratch_dir("hostile_coords_out");
  const auto r =
      run_command(kBinary + " run " + shell_quoted(kDemo) + " --input " + shell_quoted(capture) +
                  " --out " + shell_quoted(out) + " --log-level warn");
  CHECK(r.code == exit_code::kBadInput);
  CHECK(r.output.size() < 4000);
  CHECK(r.output.find_first_of("\x1b\x07") == std::string::npos);
  CHECK(contains(r.output, "vlm.coords: '\\x1B]0;pwned\\x07xxx"));
  CHECK(contains(r.output, "... (1000010 bytes)' is not one of {"));
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["error"]["message"].get<std::string>().size() < 4000);
}
