#include "runtime/atomic_file.hpp"

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace gslift {

namespace fs = std::filesystem;

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  static std::atomic<unsigned> counter{0};
  if (target.has_parent_path()) fs::create_directories(target.parent_path());
  const fs::path tmp =
      target.parent_path() / (target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                              std::to_string(counter++) + target.extension().string());
  try {
    write(tmp);
    if (!fs::exists(tmp)) throw std::runtime_error("nothing was written to " + target.string());
    fs::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void write_file_atomically(const fs::path& target, std::string_view bytes) {
  write_atomically(target, [&](const fs::path& tmp) {
    std::ofstream f(tmp, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  });
}

}  // namespace gslift
