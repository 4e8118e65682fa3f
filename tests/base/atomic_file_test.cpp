#include <fstream>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
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
  CHECK(atomic_temporary_pid("model.gslift.tmp-8745-5.ply") == 8745);
  CHECK(atomic_temporary_pid("run.gslift.tmp-1-0.json") == 1);
  CHECK(atomic_temporary_pid("_DONE.gslift.tmp-12-3") == 12);
  CHECK(atomic_temporary_pid("model.ply") == 0);
  CHECK(atomic_temporary_pid("notes.gslift.tmp-a-1.txt") == 0);
  CHECK(atomic_temporary_pid("important.tmp-7-7.docx") == 0);  // the user's, not gslift's
  // A process id that is gone: a reaped child.
  const pid_t gone = fork();
  if (gone == 0) _exit(0);
  waitpid(gone, nullptr, 0);
  const std::string dead = std::to_string(gone), live = std::to_string(getpid());
  fs::create_directories(dir / "render" / "views");
  fs::create_directories(dir / "other");
  std::ofstream(dir / "render" / "views" / ("cam_01_depth.gslift.tmp-" + dead + "-5.png"))
      << "half a PNG";
  std::ofstream(dir / ("run.gslift.tmp-" + dead + "-9.json")) << "{";
  std::ofstream(dir / ("run.gslift.tmp-" + live + "-1.json")) << "{";        // still being written
  std::ofstream(dir / "other" / ("x.gslift.tmp-" + dead + "-1.png")) << "";  // not a run folder
  write_file_atomically(dir / "render" / "cam_00_rgb.png", "whole");
  CHECK(remove_stale_temporaries(dir, {"render"}) == 2);
  CHECK(entries(dir / "render" / "views") == 0);
  CHECK(read(dir / "render" / "cam_00_rgb.png") == "whole");
  CHECK(fs::exists(dir / ("run.gslift.tmp-" + live + "-1.json")));
  CHECK(entries(dir / "other") == 1);
  CHECK(remove_stale_temporaries(dir / "missing", {}) == 0);
}

TEST_CASE("temporaries of names as long as a file name may be still fit", "[atomic]") {
  // A 250-byte name is legal; its temporary (.gslift.tmp-<pid>-<n>) was not, and the write failed.
  const fs::path dir = test::scratch_dir("atomic_long_name");
  const std::string name = std::string(246, 'n') + ".png";
  write_file_atomically(dir / name, "whole");
  CHECK(read(dir / name) == "whole");
  CHECK(entries(dir) == 1);
  // Shortened names keep long names apart and never split a UTF-8 character.
  const std::string a = std::string(250, 'a') + "1", b = std::string(250, 'a') + "2";
  CHECK(fitting_name(a, 9).size() <= kMaxNameBytes - 9);
  CHECK(fitting_name(a, 9) != fitting_name(b, 9));
  CHECK(fitting_name("short", 9) == "short");
  std::string accents;
  while (accents.size() < 300) accents += "\xc3\xa9";  // é
  const std::string fitted = fitting_name(accents, 0);
  CHECK(fitted.size() <= kMaxNameBytes);
  CHECK(fitted.substr(0, fitted.find('~')).size() % 2 == 0);
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
