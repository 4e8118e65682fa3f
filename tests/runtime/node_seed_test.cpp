#include "runtime/node_seed.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("node seeds depend on both the run seed and the node id", "[seed]") {
  CHECK(node_seed(0, "recon") == splitmix64(splitmix64(0) ^ fnv1a64("recon")));
  CHECK(node_seed(0, "recon") != node_seed(1, "recon"));
  CHECK(node_seed(0, "recon") != node_seed(0, "lift"));
  CHECK(node_seed(5, "recon") == node_seed(5, std::string("rec") + "on"));
}
