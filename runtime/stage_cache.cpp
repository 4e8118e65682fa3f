#include "runtime/stage_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "base/atomic_file.hpp"
#include "base/cache_root.hpp"
#include "base/hash.hpp"
#include "runtime/registry.hpp"
#include "runtime/version.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

// "GSLIFT stage cache, entry format 1": the first bytes of every entry.
// The magic, then the entry's whole size (uint64): a reader reads no more than that.
constexpr std::string_view kMagic = "GSLCACHE2";
constexpr size_t kHeaderBytes = kMagic.size() + 8;

std::string hex16(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
  return buf;
}

std::optional<uint64_t> file_digest(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  uint64_t h = kFnv1a64Basis;
  std::string buf(1 << 20, '\0');
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    h = fnv1a64_update(h, std::string_view(buf.data(), static_cast<size_t>(in.gcount())));
  }
  return h;
}

// Params as the key sees them: doubles with all 17 significant digits (the graph's own
// rendering keeps 15), everything else as the graph prints it.
std::string key_value(const ParamValue& v) {
  const auto exact = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return std::string(buf);
  };
  if (const double* x = std::get_if<double>(&v)) return exact(*x);
  if (const auto* xs = std::get_if<std::vector<double>>(&v)) {
    std::string out = "[";
    for (size_t i = 0; i < xs->size(); ++i) out += (i ? ", " : "") + exact((*xs)[i]);
    return out + "]";
  }
  return to_string(v);
}

bool is_entry_name(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.size() == 20 && p.extension() == ".gsc" &&
         name.find_first_not_of("0123456789abcdef") == 16;
}

}  // namespace

const std::string& build_identity() {
  static const std::string id = [] {
    std::string s = std::string("gslift ") + gslift_version() + " " + gslift_git_version();
    const std::string git = gslift_git_version();
    if (git.find("dirty") != std::string::npos || git.empty() || git == "unknown") {
      const auto exe = file_digest("/proc/self/exe");
      s += " exe " + (exe ? hex16(*exe) : std::string("unreadable"));
    }
    return s;
  }();
  return id;
}

std::optional<uint64_t> path_digest(const fs::path& path) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec) return std::nullopt;
  if (fs::is_regular_file(status)) return file_digest(path);
  if (!fs::is_directory(status)) return std::nullopt;
  std::vector<std::pair<std::string, uint64_t>> files;
  // Symlinked folders are followed (captures link image folders), with the iterator's own loop
  // protection; unreadable entries are skipped (the node will say what it could not read).
  for (auto it = fs::recursive_directory_iterator(path,
                                                  fs::directory_options::follow_directory_symlink |
                                                      fs::directory_options::skip_permission_denied,
                                                  ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it.depth() > 32) {
      it.disable_recursion_pending();
      continue;
    }
    std::error_code fec;
    if (!it->is_regular_file(fec)) continue;
    if (const auto d = file_digest(it->path()))
      files.emplace_back(fs::relative(it->path(), path, fec).generic_string(), *d);
  }
  std::sort(files.begin(), files.end());
  uint64_t h = kFnv1a64Basis;
  for (const auto& [name, digest] : files)
    h = fnv1a64_update(h, name + "\n" + hex16(digest) + "\n");
  return h;
}

StageKey stage_key(const GraphNode& node, const NodeSpec& spec, const Registry& registry,
                   uint64_t node_seed, const std::string& run_input,
                   const std::map<std::string, std::string>& input_keys) {
  std::ostringstream text;
  text << "build " << build_identity() << "\n";
  text << "type " << node.type << "\n";
  for (const auto& out : spec.outputs) {
    const PortCodec* codec = registry.codec(out.type);
    text << "output " << out.name << " " << out.type << " v" << (codec ? codec->version : 0)
         << "\n";
  }
  text << "seed " << node_seed << "\n";
  text << "run_input " << run_input << "\n";
  for (const auto& [name, value] : node.params) {
    text << "param " << name << "=" << key_value(value) << "\n";
    const ParamSpec* p = spec.find_param(name);
    if (p && p->path && std::holds_alternative<std::string>(value)) {
      const auto digest = path_digest(std::get<std::string>(value));
      if (digest) text << "content " << name << " " << hex16(*digest) << "\n";
    }
  }
  for (const auto& [port, key] : input_keys) text << "input " << port << "=" << key << "\n";
  StageKey key;
  key.text = text.str();
  key.hash = hex16(fnv1a64(key.text));
  return key;
}

FolderSnapshot snapshot_files(const fs::path& dir) {
  FolderSnapshot files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code fec;
    if (it->is_regular_file(fec))
      files[fs::relative(it->path(), dir, fec)] = it->last_write_time(fec);
  }
  return files;
}

std::vector<fs::path> files_written(const fs::path& dir, const FolderSnapshot& before) {
  std::vector<fs::path> written;
  for (const auto& [rel, time] : snapshot_files(dir)) {
    auto it = before.find(rel);
    if (it == before.end() || it->second != time) written.push_back(rel);
  }
  return written;
}

fs::path default_cache_dir() {
  if (const char* d = std::getenv("GSLIFT_STAGE_CACHE"); d && *d) return d;
  return user_cache_root() / "stages";
}

StageCache::StageCache(fs::path dir, uint64_t max_bytes)
    : dir_(std::move(dir)), max_bytes_(max_bytes) {}

fs::path StageCache::entry_path(const std::string& hash) const {
  return dir_ / (hash + ".gsc");
}

std::optional<CachedStage> StageCache::load(const StageKey& key, const Registry& registry,
                                            const fs::path& files_to) {
  const fs::path file = entry_path(key.hash);
  const auto damaged = [&](const std::string& why) -> std::optional<CachedStage> {
    spdlog::warn("stage cache: entry {} is damaged ({}): recomputing it", file.string(), why);
    std::error_code ec;
    fs::remove(file, ec);
    return std::nullopt;
  };
  std::string bytes;
  {
    // Only a regular file, not through a symlink, and no more bytes than its header claims: an
    // entry that is a FIFO would block the run, a link to /dev/zero be read until memory ends.
    const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      if (errno == ENOENT) return std::nullopt;
      return damaged(errno == ELOOP ? "a symlink" : std::strerror(errno));
    }
    struct Close {
      int fd;
      ~Close() { ::close(fd); }
    } close_fd{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return damaged("not a regular file");
    const auto read_up_to = [&](size_t n) {
      const size_t at = bytes.size();
      bytes.resize(at + n);
      size_t got = 0;
      while (got < n) {
        const ssize_t r = ::read(fd, bytes.data() + at + got, n - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        got += static_cast<size_t>(r);
      }
      bytes.resize(at + got);
      return got == n;
    };
    if (!read_up_to(kHeaderBytes) || bytes.compare(0, kMagic.size(), kMagic) != 0)
      return damaged("not a gslift cache entry");
    uint64_t claimed = 0;
    std::memcpy(&claimed, bytes.data() + kMagic.size(), 8);
    if (claimed != static_cast<uint64_t>(st.st_size) || claimed < kHeaderBytes + 8)
      return damaged("holds " + std::to_string(st.st_size) + " bytes, its header claims " +
                     std::to_string(claimed));
    if (!read_up_to(claimed - kHeaderBytes)) return damaged("truncated");
  }
  const std::string_view body(bytes.data(), bytes.size() - 8);
  uint64_t stored_sum = 0;
  std::memcpy(&stored_sum, bytes.data() + body.size(), 8);
  if (fnv1a64(body) != stored_sum) return damaged("checksum mismatch");

  CachedStage stage;
  std::vector<std::pair<std::string, std::string>> files;
  try {
    ByteReader r(body.substr(kHeaderBytes));
    if (r.get_string() != key.text) return std::nullopt;  // a hash collision: not our entry
    for (uint64_t n = r.count(9), i = 0; i < n; ++i) {
      std::string name = r.get_string();
      if (r.get<uint8_t>() == 0)
        stage.records[name] = r.get<double>();
      else
        stage.records[name] = r.get_string();
    }
    for (uint64_t n = r.count(24), i = 0; i < n; ++i) {
      const std::string port = r.get_string();
      const std::string type = r.get_string();
      const std::string payload = r.get_string();
      const PortCodec* codec = registry.codec(type);
      if (!codec) return damaged("port '" + port + "' has type " + type + " without a codec");
      ByteReader pr(payload);
      stage.outputs[port] = codec->read(pr);
      if (!pr.done()) return damaged("port '" + port + "' has trailing bytes");
    }
    const bool has_files = r.get<uint8_t>() != 0;
    if (!files_to.empty() && !has_files) return std::nullopt;  // stored by a run without --out
    for (uint64_t n = r.count(16), i = 0; i < n; ++i) {
      std::string name = r.get_string();
      files.emplace_back(std::move(name), r.get_string());
    }
    if (!r.done()) return damaged("trailing bytes");
  } catch (const std::exception& e) {
    return damaged(e.what());
  }
  if (!files_to.empty()) {
    for (const auto& [name, content] : files) {
      const fs::path rel(name);
      const bool escapes =
          rel.is_absolute() ||
          std::any_of(rel.begin(), rel.end(), [](const fs::path& c) { return c == ".."; });
      if (escapes) return damaged("file name '" + name + "' leaves the node's folder");
      write_file_atomically(files_to / rel, content);
    }
  }
  // Least recently used: a hit makes the entry young again.
  std::error_code ec;
  fs::last_write_time(file, fs::file_time_type::clock::now(), ec);
  return stage;
}

void StageCache::store(const StageKey& key, const Registry& registry,
                       const std::map<std::string, Value>& outputs,
                       const std::map<std::string, RecordValue>& records,
                       const fs::path& files_from, const std::vector<fs::path>& files) {
  try {
    ByteWriter w;
    w.put_string(key.text);
    w.put<uint64_t>(records.size());
    for (const auto& [name, value] : records) {
      w.put_string(name);
      w.put<uint8_t>(static_cast<uint8_t>(value.index()));
      if (const double* d = std::get_if<double>(&value))
        w.put<double>(*d);
      else
        w.put_string(std::get<std::string>(value));
    }
    w.put<uint64_t>(outputs.size());
    for (const auto& [port, value] : outputs) {
      const PortCodec* codec = registry.codec(value.type_name());
      if (!codec) throw std::logic_error("port type " + value.type_name() + " has no codec");
      ByteWriter payload;
      codec->write(value, payload);
      w.put_string(port);
      w.put_string(value.type_name());
      w.put_string(payload.bytes());
    }
    w.put<uint8_t>(!files_from.empty());
    w.put<uint64_t>(files.size());
    for (const auto& rel : files) {
      std::ifstream in(files_from / rel, std::ios::binary);
      std::ostringstream content;
      content << in.rdbuf();
      if (!in) throw std::runtime_error("cannot read " + (files_from / rel).string());
      w.put_string(rel.generic_string());
      w.put_string(content.str());
    }
    std::string entry = std::string(kMagic) + std::string(8, '\0') + w.take();
    const uint64_t size = entry.size() + 8;  // with the checksum
    std::memcpy(entry.data() + kMagic.size(), &size, 8);
    const uint64_t sum = fnv1a64(std::string_view(entry).substr(0));
    entry.append(reinterpret_cast<const char*>(&sum), 8);
    write_file_atomically(entry_path(key.hash), entry);
  } catch (const std::exception& e) {
    spdlog::warn("stage cache: could not store an entry in {}: {}", dir_.string(), e.what());
    return;
  }
  evict();
}

void StageCache::evict() {
  std::error_code ec;
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    uintmax_t bytes;
  };
  std::vector<Entry> entries;
  uintmax_t total = 0;
  const auto now = fs::file_time_type::clock::now();
  for (auto it = fs::directory_iterator(dir_, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    std::error_code fec;
    const auto used = it->last_write_time(fec);
    if (fec) continue;
    if (!is_entry_name(it->path())) {
      // write_file_atomically's temporary names: a writer that died an hour ago left them.
      if (atomic_temporary_pid(it->path()) != 0 && now - used > std::chrono::hours(1))
        fs::remove(it->path(), fec);
      continue;
    }
    const uintmax_t bytes = it->file_size(fec);
    if (fec) continue;
    entries.push_back({it->path(), used, bytes});
    total += bytes;
  }
  if (max_bytes_ == 0 || total <= max_bytes_) return;
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const auto& e : entries) {
    if (total <= max_bytes_) break;
    // Another process may have removed it already: that is the same outcome.
    std::error_code rec;
    fs::remove(e.path, rec);
    total -= e.bytes;
  }
}

}  // namespace gslift
