#include <fstream>
#include <stdexcept>

#include "base/errors.hpp"
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

TEST_CASE("a killed run's temporaries are recognised and removed, nothing else", "[atomic]") {
  const fs::path dir = test::scratch_dir("atomic_stale");
  CHECK(is_atomic_temporary("model.tmp-8745-5.ply"));
  CHECK(is_atomic_temporary("run.tmp-1-0.json"));
  CHECK(is_atomic_temporary("_DONE.tmp-12-3"));
  CHECK_FALSE(is_atomic_temporary("model.ply"));
  CHECK_FALSE(is_atomic_temporary("notes.tmp-a-1.txt"));
  CHECK_FALSE(is_atomic_temporary("cam.tmp.png"));
  fs::create_directories(dir / "render");
  std::ofstream(dir / "render" / "cam_01_depth.tmp-8745-5.png") << "half a PNG";
  std::ofstream(dir / "run.tmp-8745-9.json") << "{";
  write_file_atomically(dir / "render" / "cam_00_rgb.png", "whole");
  CHECK(remove_stale_temporaries(dir) == 2);
  CHECK(entries(dir / "render") == 1);
  CHECK(read(dir / "render" / "cam_00_rgb.png") == "whole");
  CHECK(remove_stale_temporaries(dir / "missing") == 0);
}

TEST_CASE("a file that cannot be written is an OutputError naming it and why", "[atomic]") {
  const fs::path dir = test::scratch_dir("atomic_output_error");
  std::ofstream(dir / "blocker") << "a file where a folder should be";
  try {
    write_file_atomically(dir / "blocker" / "run.json", "{}");
    FAIL("no error");
  } catch (const OutputError& e) {
    CHECK_THAT(e.what(),
               Catch::Contains((dir / "blocker").string()) && Catch::Contains("Not a directory"));
  }
  CHECK(entries(dir) == 1);
}
