// End-to-end tests of the gslift executable with the built-in node catalogue.
#include <fstream>
#include <sstream>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
namespace fs = std::filesystem;

namespace {
const std::string kBinary = GSLIFT_BINARY;
}

TEST_CASE("--help lists the commands and exit codes, globally and per command", "[cli]") {
  for (const char* flag : {" --help", " -h"}) {
    const auto r = run_command(kBinary + flag);
    CHECK(r.code == exit_code::kOk);
    for (const char* word : {"run", "validate", "nodes", "batch", "130", "invalid graph"})
      CHECK(r.output.find(word) != std::string::npos);
  }
  for (const char* cmd : {"run", "validate", "nodes", "batch"}) {
    const auto r = run_command(kBinary + " " + cmd + " --help");
    INFO(cmd);
    CHECK(r.code == exit_code::kOk);
    CHECK(r.output.find(std::string("usage: gslift ") + cmd) != std::string::npos);
    CHECK(r.output.find("exit codes:") != std::string::npos);
  }
  // No command at all is a usage error that still shows the help.
  const auto none = run_command(kBinary);
  CHECK(none.code == exit_code::kUsage);
  CHECK(none.output.find("commands:") != std::string::npos);
}

TEST_CASE("--version prints the project and git versions", "[cli]") {
  const auto r = run_command(kBinary + " --version");
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.rfind("gslift 0.1.0 (", 0) == 0);
}

TEST_CASE("an unknown command is a usage error with a suggestion", "[cli]") {
  const auto r = run_command(kBinary + " rnu graphs/demo.yaml");
  CHECK(r.code == exit_code::kUsage);
  CHECK(r.output.find("unknown command 'rnu' (did you mean 'run'?)") != std::string::npos);
}

TEST_CASE("validate reports an invalid graph with file:line and exit code 3", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_validate_invalid");
  const fs::path graph = dir / "bad.yaml";
  std::ofstream(graph) << "graph: bad\nnodes:\n  x: {type: no.such_type}\n";
  const auto r = run_command(kBinary + " validate '" + graph.string() + "'");
  INFO(r.output);
  CHECK(r.code == exit_code::kInvalidGraph);
  CHECK(r.output.find(graph.string() + ":3:") != std::string::npos);
  CHECK(r.output.find("no.such_type") != std::string::npos);
}

TEST_CASE("nodes lists the catalogue and documents every listed type", "[cli]") {
  const auto list = run_command(kBinary + " nodes");
  REQUIRE(list.code == exit_code::kOk);
  std::istringstream lines(list.output);
  std::string line;
  int types = 0;
  while (std::getline(lines, line)) {
    const std::string type = line.substr(0, line.find(' '));
    const auto page = run_command(kBinary + " nodes " + type);
    INFO(type);
    CHECK(page.code == exit_code::kOk);
    CHECK(page.output.rfind(type + ": ", 0) == 0);
    CHECK(page.output.find("\ninputs:\n") != std::string::npos);
    CHECK(page.output.find("\nparams:\n") != std::string::npos);
    ++types;
  }
  WARN(types << " node types registered");
}
