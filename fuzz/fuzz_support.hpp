// Shared by the libFuzzer targets (fuzz/README.md, docs/security.md). Every target feeds its
// input to one reader and accepts exactly one outcome besides success: gslift::InputError, the
// project's "bad input" (the charter: a clear InputError, never a crash). Any other exception
// escapes and libFuzzer reports it as a crash, like a sanitizer report or a timeout.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/errors.hpp"

namespace gslift::fuzz {

// This process's scratch folder for readers that take paths (one fuzzer process runs one input at
// a time, so one folder per process is enough).
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("gslift_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::filesystem::path write_file(const std::filesystem::path& file,
                                        const std::string& bytes) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  return file;
}

// The input cut at each occurrence of kSplit into at most `n` parts (the last takes the rest), so
// that one input can fill several files of a model folder; missing parts are empty.
constexpr const char* kSplit = "\n#GSLIFT-FUZZ-FILE#\n";
inline std::vector<std::string> split_input(const std::string& data, size_t n) {
  std::vector<std::string> parts;
  const std::string sep = kSplit;
  size_t start = 0;
  while (parts.size() + 1 < n) {
    const size_t at = data.find(sep, start);
    if (at == std::string::npos) break;
    parts.push_back(data.substr(start, at - start));
    start = at + sep.size();
  }
  parts.push_back(data.substr(start));
  parts.resize(n);
  return parts;
}

// Runs `read` and swallows InputError, the one accepted failure.
template <class Fn>
void expect_input_error_only(Fn read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace gslift::fuzz
