#include "runtime/atomic_file.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "base/errors.hpp"

namespace gslift {

namespace fs = std::filesystem;

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  static std::atomic<unsigned> counter{0};
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec)
      throw OutputError("cannot create folder " + target.parent_path().string() + ": " +
                        ec.message());
  }
  const fs::path tmp =
      target.parent_path() / (target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                              std::to_string(counter++) + target.extension().string());
  try {
    write(tmp);
    if (!fs::exists(tmp)) throw std::runtime_error("nothing was written to " + target.string());
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw OutputError("cannot write " + target.string() + ": " + ec.message());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_file_atomically(const fs::path& target, std::string_view bytes) {
  write_atomically(target, [&](const fs::path& tmp) {
    // stdio rather than a stream: every failure (open, a short write, the flush at close) keeps
    // its errno, so the message can say "No space left on device" rather than "cannot write".
    errno = 0;
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    const auto fail = [&](int err) {
      return OutputError("cannot write " + target.string() + ": " +
                         (err ? std::strerror(err) : "write failed"));
    };
    if (!f) throw fail(errno);
    const size_t written = std::fwrite(bytes.data(), 1, bytes.size(), f);
    const int write_errno = written == bytes.size() ? 0 : (errno ? errno : EIO);
    errno = 0;
    const bool closed = std::fclose(f) == 0;
    if (write_errno) throw fail(write_errno);
    if (!closed) throw fail(errno);
  });
}

bool is_atomic_temporary(const fs::path& name) {
  static const std::regex pattern(R"(.*\.tmp-[0-9]+-[0-9]+(\..*)?)");
  return std::regex_match(name.filename().string(), pattern);
}

size_t remove_stale_temporaries(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return 0;
  std::vector<fs::path> stale;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec))
    if (it->is_regular_file(ec) && is_atomic_temporary(it->path())) stale.push_back(it->path());
  for (const auto& p : stale) fs::remove(p, ec);
  return stale.size();
}

}  // namespace gslift
