#include "base/atomic_file.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include <signal.h>
#include <unistd.h>

#include "base/errors.hpp"
#include "base/hash.hpp"

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
  // The extension stays last (cv::imwrite picks its encoder by it); the stem gives way when the
  // temporary would be longer than a file name may be.
  const std::string tag = ".gslift.tmp-" + std::to_string(::getpid()) + "-" +
                          std::to_string(counter++) + target.extension().string();
  const fs::path tmp =
      target.parent_path() / (fitting_name(target.stem().string(), tag.size()) + tag);
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

std::string fitting_name(const std::string& name, size_t extra_bytes) {
  if (name.size() + extra_bytes <= kMaxNameBytes) return name;
  char hash[18];
  std::snprintf(hash, sizeof hash, "~%016llx", static_cast<unsigned long long>(fnv1a64(name)));
  const size_t room = kMaxNameBytes - std::min(kMaxNameBytes, extra_bytes + sizeof hash - 1);
  size_t keep = std::min(room, name.size());
  // Not into the middle of a UTF-8 character: back off its continuation bytes and its lead.
  while (keep > 0 && keep < name.size() && (static_cast<unsigned char>(name[keep]) & 0xC0) == 0x80)
    --keep;
  return name.substr(0, keep) + hash;
}

int atomic_temporary_pid(const fs::path& name) {
  static const std::regex pattern(R"(.*\.gslift\.tmp-([0-9]{1,9})-[0-9]+(\..*)?)");
  std::smatch m;
  const std::string file = name.filename().string();
  if (!std::regex_match(file, m, pattern)) return 0;
  return std::stoi(m[1].str());
}

namespace {

// Whether the process that named a temporary is gone (its id may have been reused since: then the
// temporary stays until a later run, which is harmless).
bool process_gone(int pid) {
  return pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH;
}

void collect_stale(const fs::path& file, std::vector<fs::path>& stale) {
  std::error_code ec;
  if (fs::symlink_status(file, ec).type() == fs::file_type::regular &&
      process_gone(atomic_temporary_pid(file)))
    stale.push_back(file);
}

}  // namespace

size_t remove_stale_temporaries(const fs::path& out, const std::vector<std::string>& folders) {
  std::error_code ec;
  if (!fs::is_directory(out, ec)) return 0;
  std::vector<fs::path> stale;
  for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    collect_stale(it->path(), stale);
  for (const auto& f : folders) {
    const fs::path folder = out / f;
    // A folder that is a symlink leads somewhere gslift did not make: not followed.
    if (fs::symlink_status(folder, ec).type() != fs::file_type::directory) continue;
    for (auto it = fs::recursive_directory_iterator(folder, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      collect_stale(it->path(), stale);
  }
  for (const auto& p : stale) fs::remove(p, ec);
  return stale.size();
}

}  // namespace gslift
