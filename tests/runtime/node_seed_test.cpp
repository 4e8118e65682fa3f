#include "runtime/node_seed.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("seed hashes match their published reference values", "[seed]") {
  // FNV-1a 64 test vectors (offset basis for "", and "a").
  CHECK(fnv1a64("") == 0xcbf29ce484222325ULL);
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cULL);
  // First output of Vigna's splitmix64 generator seeded with 0.
  CHECK(splitmix64(0) == 0xe220a8397b1dcdafULL);
}

TEST_CASE("node seeds depend on both the run seed and the node id", "[seed]") {
  CHECK(node_seed(0, "recon") == splitmix64(splitmix64(0) ^ fnv1a64("recon")));
  CHECK(node_seed(0, "recon") != node_seed(1, "recon"));
  CHECK(node_seed(0, "recon") != node_seed(0, "lift"));
  CHECK(node_seed(5, "recon") == node_seed(5, std::string("rec") + "on"));
}
