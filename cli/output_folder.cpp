#include "cli/output_folder.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "base/errors.hpp"

namespace gslift {

namespace fs = std::filesystem;

void check_output_folder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError("--out " + out.string() + " exists and is not a folder");
  fs::create_directories(out, ec);
  if (ec) throw OutputError("cannot create --out " + out.string() + ": " + ec.message());
  if (::access(out.c_str(), W_OK | X_OK) != 0)
    throw OutputError("cannot write in --out " + out.string() + ": " + std::strerror(errno));
}

void check_results_folder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out / "run.json", ec)) return;
  for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename() != "gslift.log")
      throw InputError("--out " + out.string() +
                       " is not empty and holds no run.json: not a gslift results folder (name a "
                       "new or empty folder)");
}

std::string results_line(const fs::path& out) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out))
    names.push_back(e.path().filename().string() + (e.is_directory() ? "/" : ""));
  std::sort(names.begin(), names.end());
  std::string list;
  for (size_t i = 0; i < names.size() && i < 8; ++i) list += (i ? ", " : "") + names[i];
  if (names.size() > 8) list += ", ...";
  return out.string() + " (" + list + ")";
}

}  // namespace gslift
