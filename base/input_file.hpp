// Input files are untrusted (docs/security.md): a capture, a graph or a manifest may name a
// directory, a FIFO, /dev/zero or a symlink loop where a file belongs, and a capture may name
// files outside its own folder. These checks turn each of those into an InputError naming the
// path, before anything is opened (a directory opens and then fails inside the stream with
// "basic_filebuf::underflow"; /dev/zero reads until memory runs out; a FIFO blocks forever).
// Standard library only, like everything in base/.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "base/errors.hpp"
#include "base/utf8.hpp"

namespace gslift {

// Throws InputError unless `path` is a regular file (after following symlinks): "does not
// exist", "is a directory", "is a symlink loop" or "is not a regular file (a FIFO, socket or
// device)", each naming the path. `what` says what the file is for ("capture.yaml", ...).
inline void require_regular_file(const std::filesystem::path& path,
                                 const std::string& what = "input file") {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);
  if (ec == std::errc::too_many_symbolic_link_levels)
    throw InputError(path.string() + ": " + what + " is a symlink loop");
  if (ec || !fs::exists(s)) throw InputError(path.string() + ": " + what + " does not exist");
  if (fs::is_directory(s))
    throw InputError(path.string() + ": " + what + " is a directory, not a file");
  if (!fs::is_regular_file(s))
    throw InputError(path.string() + ": " + what +
                     " is not a regular file (a FIFO, socket or device)");
}

// Whether anything is at `path`: a file, a directory, a FIFO, a dangling or looping symlink.
// Optional entries (a view's depth prior, a VLM reply, a SAM record) test this rather than
// is_regular_file, so that an entry that is there but unreadable is an error naming it instead of
// silently "missing".
inline bool entry_exists(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(std::filesystem::symlink_status(path, ec));
}

// The whole of a regular file (require_regular_file first).
inline std::string read_input_file(const std::filesystem::path& path,
                                   const std::string& what = "input file") {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open " + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": cannot read " + what);
  return ss.str();
}

// Whether `file`, with symlinks followed as far as they exist, lies inside `folder` (also
// resolved). `../`, absolute paths and symlinks that leave the folder all fail.
inline bool lies_inside(const std::filesystem::path& folder, const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(folder), ec);
  if (ec) return false;
  const fs::path target = fs::weakly_canonical(fs::absolute(file), ec);
  if (ec) return false;
  auto r = root.begin(), t = target.begin();
  for (; r != root.end(); ++r, ++t) {
    if (r->empty()) continue;  // the trailing "" of a path ending in '/'
    if (t == target.end() || *r != *t) return false;
  }
  return true;
}

// The one containment check of ingest: every file and folder it opens in a capture goes through
// this (or path_inside, which does). `file` is refused unless it lies inside `folder` (symlinks
// followed) or `allow_outside` (the ingest param allow_outside_paths) says the capture is
// trusted; `where` names what pointed there.
inline const std::filesystem::path& require_inside(const std::filesystem::path& folder,
                                                   const std::filesystem::path& file,
                                                   bool allow_outside, const std::string& where) {
  if (!allow_outside && !lies_inside(folder, file))
    throw InputError(where + ": '" + file.string() + "' points outside " + folder.string() +
                     " (set the ingest param allow_outside_paths to follow it)");
  return file;
}

// `folder / name` for a name read from a capture file (`where`: "file:line" or "file (what)"),
// refused unless it stays inside `folder` or `allow_outside` (the ingest param
// allow_outside_paths) says the capture is trusted.
inline std::filesystem::path path_inside(const std::filesystem::path& folder,
                                         const std::string& name, bool allow_outside,
                                         const std::string& where) {
  if (name.find('\0') != std::string::npos)
    throw InputError(where + ": file name contains a NUL byte");
  const std::filesystem::path p = folder / name;
  if (!allow_outside && !lies_inside(folder, p))
    throw InputError(where + ": '" + printable(name) + "' points outside " + folder.string() +
                     " (set the ingest param allow_outside_paths to follow it)");
  return p;
}

}  // namespace gslift
