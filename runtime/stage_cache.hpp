// The stage cache: content-addressed results per node, so that a changed downstream param never
// reruns the reconstruction (issue 15). A node's key is a hash of a canonical text naming
// everything its outputs depend on: the gslift build, the binary form of its output types, its
// type, resolved params, the content of the files its path params name, its seed and the keys of
// its inputs (which name their producers' in turn). An entry holds the node's outputs (binary
// port forms, nodes/scene/port_archive.hpp), its run records and the files it wrote; loading it
// stands in for running the node.
//
// One entry is one file, written under a temporary name and renamed, and ends in a checksum:
// two processes may share a cache folder (the last rename wins, with the same bytes; a reader
// keeps the inode it opened even if another process evicts it), and a truncated or corrupt entry
// is detected, removed and recomputed, never loaded. The key text is stored in the entry and
// compared on load, so a 64-bit hash collision is a miss, not a wrong result. Eviction is least
// recently used: a hit touches the entry's mtime; after each store the oldest entries go until
// the folder is under its size cap.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "graph/graph.hpp"
#include "graph/node_spec.hpp"
#include "runtime/value.hpp"

namespace gslift {

class Registry;

using RecordValue = std::variant<double, std::string>;

// A node's key: `text` is canonical and human-readable (stored in the entry), `hash` its 16 hex
// digits (the entry's file name and what consumers' keys name).
struct StageKey {
  std::string text;
  std::string hash;
};

// input_keys: port -> "<producer hash>.<producer port>". run_input: the run's --input, which a
// node may read (ctx.run_input()) besides its params.
StageKey stage_key(const GraphNode& node, const NodeSpec& spec, const Registry& registry,
                   uint64_t node_seed, const std::string& run_input,
                   const std::map<std::string, std::string>& input_keys);

// What identifies this build's code: version and git commit, plus a digest of the running
// executable when the tree was dirty (or the commit unknown), so a rebuilt binary with edits
// never loads its predecessor's results.
const std::string& build_identity();

// FNV-1a of a file's bytes; of a folder, of its regular files' relative names and digests in
// sorted order; of anything else (a missing path, "embedded:or"), nothing: the param's text in
// the key stands for it.
std::optional<uint64_t> path_digest(const std::filesystem::path& path);

struct CachedStage {
  std::map<std::string, Value> outputs;
  std::map<std::string, RecordValue> records;
};

class StageCache {
 public:
  // max_bytes: the size cap of the folder's entries (0 = no cap).
  StageCache(std::filesystem::path dir, uint64_t max_bytes);

  const std::filesystem::path& dir() const { return dir_; }

  // The entry for `key`, or nothing (absent, damaged, or written without the files the run needs:
  // `files_to` non-empty asks for them, restored there). A damaged entry is removed and warned
  // about. Never throws for the cache's own troubles: they are misses.
  std::optional<CachedStage> load(const StageKey& key, const Registry& registry,
                                  const std::filesystem::path& files_to);

  // Stores a node's results. `files_from` (empty for a run without an output folder) is the
  // node's output folder and `files` the files the node wrote there (relative paths; see
  // files_written). Failures (a full disk) are warned about and leave no entry.
  void store(const StageKey& key, const Registry& registry,
             const std::map<std::string, Value>& outputs,
             const std::map<std::string, RecordValue>& records,
             const std::filesystem::path& files_from,
             const std::vector<std::filesystem::path>& files);

  // Removes least recently used entries until the folder holds at most max_bytes, and temporary
  // files of writers that died (older than an hour).
  void evict();

  std::filesystem::path entry_path(const std::string& hash) const;

 private:
  std::filesystem::path dir_;
  uint64_t max_bytes_;
};

// The regular files under `dir` with their modification times (empty when there is no folder).
using FolderSnapshot = std::map<std::filesystem::path, std::filesystem::file_time_type>;
FolderSnapshot snapshot_files(const std::filesystem::path& dir);
// The files under `dir` that are new or rewritten since `before` (relative paths, sorted): what a
// node wrote, not what earlier runs into the same folder left there.
std::vector<std::filesystem::path> files_written(const std::filesystem::path& dir,
                                                 const FolderSnapshot& before);

// $GSLIFT_STAGE_CACHE, else <user_cache_root()>/stages (~/.cache/gslift/stages).
std::filesystem::path default_cache_dir();

}  // namespace gslift
