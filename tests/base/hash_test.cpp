// The project's hashes against published reference values.
#include "base/hash.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("FNV-1a 64 matches its published test vectors", "[hash]") {
  CHECK(fnv1a64("") == 0xcbf29ce484222325ull);  // the offset basis
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a64("foobar") == 0x85944171f73967e8ull);
  // Bytes, not chars: a byte >= 0x80 is hashed as unsigned.
  CHECK(fnv1a64("\xff") == ((0xcbf29ce484222325ull ^ 0xffull) * 0x100000001b3ull));
  static_assert(fnv1a64("a") == 0xaf63dc4c8601ec8cull, "usable in constant expressions");
  // Streamed in pieces (a file through a buffer), the same hash.
  CHECK(fnv1a64_update(fnv1a64_update(kFnv1a64Basis, "foo"), "bar") == 0x85944171f73967e8ull);
}

TEST_CASE("splitmix64 matches Vigna's reference generator", "[hash]") {
  // splitmix64.c seeded with 0 first outputs mix(0 + golden), then mix(2 golden), ...
  CHECK(splitmix64(0) == 0xe220a8397b1dcdafull);
  CHECK(splitmix64(0x9e3779b97f4a7c15ull) == 0x6e789e6aa1b965f4ull);
  CHECK(splitmix64(2 * 0x9e3779b97f4a7c15ull) == 0x06c45d188009454full);
}
