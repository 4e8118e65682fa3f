// The API key through the real command line (issue 16): `gslift run` of the embedded OR with a
// live vlm.query against a loopback server that echoes the request's headers in a 500. The key,
// read from the environment, must appear nowhere: not in the printed error, the log lines, run.json
// or any file of the results folder.
#include <fstream>
#include <sstream>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/test_support.hpp"
#include "tests/vlm/loopback_server.hpp"

namespace fs = std::filesystem;
using namespace gslift;

TEST_CASE("gslift run never prints or stores the VLM API key", "[faults]") {
  const fs::path dir = test::scratch_dir("vlm_cli_key");
  const std::string key = "sk-gslift-cli-8c1e4f";
  test::CannedResponse echo{500, ""};
  echo.echo_headers = true;
  test::LoopbackServer server({echo});
  const fs::path graph = dir / "live.yaml";
  std::ofstream(graph) << "graph: live\nnodes:\n"
                          "  capture: {type: ingest.capture, params: {path: "
                          "\"embedded:or?width=64&height=48&views=4\"}}\n"
                          "  prompt: {type: boxes.prompt, params: {vocabulary: "
                       << GSLIFT_SOURCE_DIR << "/graphs/vocabulary/or.yaml}}\n"
                       << "  vlm:\n    type: vlm.query\n"
                          "    in: {capture: capture.capture, prompt: prompt.prompt}\n"
                          "    params: {url: \""
                       << server.url()
                       << "\", rounds: 1, retries: 1, backoff_s: 0, "
                          "api_key_env: GSLIFT_TEST_KEY}\n";
  const auto r =
      test::run_command("GSLIFT_TEST_KEY=" + key + " GSLIFT_CACHE='" + (dir / "cache").string() +
                        "' " + GSLIFT_BINARY + " run '" + graph.string() + "' --out '" +
                        (dir / "out").string() + "' --threads 1 --log-level debug");
  INFO(r.output);
  CHECK(r.code == exit_code::kBadInput);
  // The server saw the key, and the message shows where it was without it.
  CHECK(server.bodies().size() == 2);
  CHECK(r.output.find("HTTP 500 after 2 attempt(s)") != std::string::npos);
  CHECK(r.output.find("Bearer [api key]") != std::string::npos);
  CHECK(r.output.find(key) == std::string::npos);
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) {
    if (!e.is_regular_file()) continue;
    ++files;
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    INFO(e.path().string());
    CHECK(s.str().find(key) == std::string::npos);
  }
  CHECK(files >= 1);  // run.json at least
}
