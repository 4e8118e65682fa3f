#include <fstream>
#include <stdexcept>

#include "runtime/atomic_file.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {
size_t entries(const fs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}
std::string read(const fs::path& f) {
  std::ifstream in(f);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
}  // namespace

TEST_CASE("a writer that throws halfway leaves no file behind", "[atomic]") {
  const fs::path dir = test::scratch_dir("atomic_throw");
  CHECK_THROWS_AS(write_atomically(dir / "out.json",
                                   [](const fs::path& tmp) {
                                     std::ofstream(tmp) << "{\"half\":";
                                     throw std::runtime_error("disk full");
                                   }),
                  std::runtime_error);
  CHECK(entries(dir) == 0);
}

TEST_CASE("a writer that writes nothing is an error and leaves no file", "[atomic]") {
  const fs::path dir = test::scratch_dir("atomic_empty");
  CHECK_THROWS(write_atomically(dir / "out.png", [](const fs::path&) {}));
  CHECK(entries(dir) == 0);
}

TEST_CASE("a failed rewrite keeps the previous complete file", "[atomic]") {
  const fs::path dir = test::scratch_dir("atomic_keep");
  write_file_atomically(dir / "sub" / "a.txt", "first");
  CHECK(read(dir / "sub" / "a.txt") == "first");
  CHECK_THROWS(write_atomically(dir / "sub" / "a.txt", [](const fs::path& tmp) {
    CHECK(tmp.extension() == ".txt");
    std::ofstream(tmp) << "sec";
    throw std::runtime_error("interrupted");
  }));
  CHECK(read(dir / "sub" / "a.txt") == "first");
  CHECK(entries(dir / "sub") == 1);
}
