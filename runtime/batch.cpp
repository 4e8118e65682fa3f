#include "runtime/batch.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "base/atomic_file.hpp"
#include "base/hash.hpp"
#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "runtime/child_process.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/node.hpp"
#include "runtime/run_record.hpp"
#include "runtime/utc_time.hpp"

namespace gslift {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::string output_name(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  std::string name = fs::path(path).filename().string();
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
  // A manifest line that is no path ("embedded:...") may be longer than a file name may be.
  return name.empty() || name == "." || name == ".." ? "capture" : fitting_name(name, 0);
}

// The last non-empty line of a child's log: the error it printed before it exited.
std::string last_log_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (!trim(line).empty()) last = trim(line);
  return last;
}

RunError::Kind error_kind(const std::string& text) {
  for (auto k : {RunError::Kind::BadInput, RunError::Kind::NodeFailed, RunError::Kind::Cancelled,
                 RunError::Kind::Output})
    if (text == to_string(k)) return k;
  return RunError::Kind::NodeFailed;
}

}  // namespace

std::vector<ManifestEntry> read_manifest(const fs::path& manifest) {
  // A directory opened as a manifest reads as empty: 0 captures and exit 0, so refuse it.
  std::istringstream in(read_input_file(manifest, "batch manifest"));
  std::vector<ManifestEntry> out;
  std::map<std::string, int> line_of_name;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    const auto hash = text.find(" #");
    if (hash != std::string::npos) text.resize(hash);
    text = trim(text);
    if (text.empty() || text[0] == '#') continue;
    ManifestEntry e;
    // "embedded:..." inputs name generated captures, not files.
    const bool is_file = text.find(':') == std::string::npos;
    e.path =
        is_file && fs::path(text).is_relative() ? (manifest.parent_path() / text).string() : text;
    e.name = output_name(text);
    e.line = line;
    e.index = out.size();
    auto [it, fresh] = line_of_name.emplace(e.name, line);
    if (!fresh)
      throw InputError(manifest.string() + ":" + std::to_string(line) + ": capture '" + text +
                       "' has the same output folder name '" + e.name + "' as line " +
                       std::to_string(it->second));
    out.push_back(std::move(e));
  }
  return out;
}

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  Shard s;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    size_t used_i = 0, used_n = 0;
    s.index = std::stoi(text.substr(0, slash), &used_i);
    s.count = std::stoi(text.substr(slash + 1), &used_n);
    if (used_i != slash || used_n != text.size() - slash - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("--shard expects i/n (e.g. 0/4), got '" + text + "'");
  }
  if (s.count < 1 || s.index < 0 || s.index >= s.count)
    throw std::invalid_argument("--shard " + text + ": need 0 <= i < n");
  return s;
}

namespace {

// A scheduler variable's value as a non-negative integer; anything else names the variable.
int env_integer(const std::string& name, const std::string& value) {
  size_t used = 0;
  long long v = -1;
  try {
    v = std::stoll(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != value.size() || v < 0 || v > std::numeric_limits<int>::max())
    throw std::invalid_argument("environment variable " + name +
                                " should be a non-negative integer, got '" + value + "'");
  return static_cast<int>(v);
}

}  // namespace

std::optional<ShardFromEnvironment> shard_from_environment(const EnvironmentLookup& env,
                                                           std::optional<int> count_option) {
  ShardFromEnvironment out;
  if (const auto id = env("SLURM_ARRAY_TASK_ID")) {
    const auto count = env("SLURM_ARRAY_TASK_COUNT");
    if (!count)
      throw std::invalid_argument(
          "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not; pass --shard I/N");
    const auto min = env("SLURM_ARRAY_TASK_MIN");
    const int task = env_integer("SLURM_ARRAY_TASK_ID", *id);
    const int first = min ? env_integer("SLURM_ARRAY_TASK_MIN", *min) : 0;
    out.shard.count = env_integer("SLURM_ARRAY_TASK_COUNT", *count);
    out.shard.index = task - first;
    out.source = "SLURM_ARRAY_TASK_ID=" + *id + " (SLURM_ARRAY_TASK_MIN=" + (min ? *min : "0") +
                 ", SLURM_ARRAY_TASK_COUNT=" + *count + ")";
    if (out.shard.count < 1 || out.shard.index < 0 || out.shard.index >= out.shard.count)
      throw std::invalid_argument(
          out.source +
          " is not shard 0 <= ID - MIN < COUNT: submit the array as a contiguous range (e.g. "
          "--array=0-3), or pass --shard I/N");
    return out;
  }
  if (const auto index = env("JOB_COMPLETION_INDEX")) {
    std::optional<int> count = count_option;
    std::string count_source = "--shard-count";
    if (!count) {
      const auto from_env = env("GSLIFT_SHARD_COUNT");
      if (!from_env)
        throw std::invalid_argument(
            "JOB_COMPLETION_INDEX is set but not the shard count: pass --shard-count N or set "
            "GSLIFT_SHARD_COUNT to the Job's completions");
      count = env_integer("GSLIFT_SHARD_COUNT", *from_env);
      count_source = "GSLIFT_SHARD_COUNT";
    }
    out.shard.index = env_integer("JOB_COMPLETION_INDEX", *index);
    out.shard.count = *count;
    out.source =
        "JOB_COMPLETION_INDEX=" + *index + " (" + count_source + " " + std::to_string(*count) + ")";
    if (out.shard.count < 1 || out.shard.index >= out.shard.count)
      throw std::invalid_argument(out.source + ": need 0 <= index < count");
    return out;
  }
  return std::nullopt;
}

std::vector<ManifestEntry> discover_captures(const fs::path& dir, const fs::path& out_root) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError("--discover " + dir.string() + " is not a folder");
  const fs::path out_canonical = fs::weakly_canonical(out_root, ec);
  std::vector<ManifestEntry> out;
  fs::directory_iterator it(dir, ec);
  if (ec) throw InputError("cannot list --discover " + dir.string() + ": " + ec.message());
  for (const auto& entry : it) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.' || name[0] == '_' || !fs::is_directory(entry.path(), ec))
      continue;
    if (fs::weakly_canonical(entry.path(), ec) == out_canonical) continue;
    ManifestEntry e;
    e.path = entry.path().string();
    e.name = output_name(name);
    if (fs::exists(out_root / e.name / "_DONE", ec)) continue;
    // The shard of a capture is a function of its name alone, so array tasks that discover at
    // slightly different moments still agree on who takes which capture.
    e.index = static_cast<size_t>(fnv1a64(e.name));
    out.push_back(std::move(e));
  }
  std::sort(out.begin(), out.end(),
            [](const ManifestEntry& a, const ManifestEntry& b) { return a.name < b.name; });
  for (size_t i = 1; i < out.size(); ++i)
    if (out[i].name == out[i - 1].name)
      throw InputError("--discover " + dir.string() + ": folders '" + out[i - 1].path + "' and '" +
                       out[i].path + "' have the same output folder name '" + out[i].name + "'");
  return out;
}

RunResult child_run_result(const ChildRun& child, const fs::path& run_dir, const fs::path& log) {
  RunResult result;
  const bool exited = child.started && WIFEXITED(child.status);
  const int code = exited ? WEXITSTATUS(child.status) : -1;
  try {
    // "running" is the record of a child that died before its end: its exit says more.
    const json record = parse_json(read_input_file(run_dir / "run.json", "run record"));
    const json& run = record.at("run");
    const std::string status = run.at("status").get<std::string>();
    if (exited && status != "running") {
      result.status = status == "ok" && code == exit_code::kOk ? RunStatus::Ok
                      : status == "interrupted"                ? RunStatus::Interrupted
                                                               : RunStatus::Failed;
      if (result.ok()) return result;
      const json& error = run.at("error");
      RunError e;
      if (error.is_object()) {
        e.kind = error_kind(error.value("kind", std::string()));
        e.node = error.value("node", std::string());
        e.type = error.value("type", std::string());
        if (error.contains("loc") && error["loc"].is_string()) e.loc.file = error["loc"];
        e.message = error.value("message", std::string());
      } else {
        e.message = "exit code " + std::to_string(code);
      }
      result.error = e;
      return result;
    }
  } catch (const std::exception&) {
    // No record, or not one: the exit status tells.
  }
  result.status = code == exit_code::kInterrupted ? RunStatus::Interrupted : RunStatus::Failed;
  RunError e;
  e.kind = code == exit_code::kCannotWrite ? RunError::Kind::Output
           : code == exit_code::kBadInput  ? RunError::Kind::BadInput
                                           : RunError::Kind::NodeFailed;
  e.message = "gslift run " + child_exit_text(child);
  const std::string said = last_log_line(log);
  if (!said.empty()) e.message += ": " + said;
  result.error = e;
  return result;
}

const char* to_string(CaptureStatus s) {
  switch (s) {
    case CaptureStatus::Done:
      return "done";
    case CaptureStatus::Skipped:
      return "skipped";
    case CaptureStatus::Failed:
      return "failed";
    case CaptureStatus::Interrupted:
      return "interrupted";
  }
  return "?";
}

int BatchSummary::count(CaptureStatus s) const {
  int n = 0;
  for (const auto& c : captures) n += c.status == s;
  return n;
}

namespace {

// A metric for the table: 4 significant digits, as the sweep table prints them.
std::string format_metric(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

// The headline metrics of the run.json in a capture's result folder; none without a readable one.
std::vector<std::pair<std::string, double>> metrics_in(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / "run.json", ec)) return {};
  try {
    return headline_metrics(parse_json(read_input_file(dir / "run.json", "run record")));
  } catch (const std::exception&) {
    return {};
  }
}

}  // namespace

json BatchSummary::json() const {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& c : captures) {
    nlohmann::json metrics = nlohmann::json::object();
    for (const auto& [key, value] : c.metrics) metrics[key] = value;
    rows.push_back({{"name", c.name},
                    {"path", c.path},
                    {"status", to_string(c.status)},
                    {"seconds", c.seconds},
                    {"metrics", metrics},
                    {"error", c.error}});
  }
  return {{"captures", rows},
          {"done", count(CaptureStatus::Done)},
          {"skipped", count(CaptureStatus::Skipped)},
          {"failed", count(CaptureStatus::Failed)},
          {"interrupted", interrupted},
          {"cannot_write", cannot_write}};
}

std::string BatchSummary::table() const {
  size_t width = 7;
  std::vector<std::string> keys;  // every metric a capture has, in order of first appearance
  for (const auto& c : captures) {
    width = std::max(width, c.name.size());
    for (const auto& m : c.metrics)
      if (std::find(keys.begin(), keys.end(), m.first) == keys.end()) keys.push_back(m.first);
  }
  std::string out;
  char row[512];
  std::snprintf(row, sizeof row, "%-*s  %-11s  %9s", static_cast<int>(width), "capture", "status",
                "seconds");
  out += row;
  for (const auto& k : keys) out += "  " + k;
  out += "  error\n";
  for (const auto& c : captures) {
    std::snprintf(row, sizeof row, "%-*s  %-11s  %9.2f", static_cast<int>(width), c.name.c_str(),
                  to_string(c.status), c.seconds);
    out += row;
    for (const auto& k : keys) {
      const auto m = std::find_if(c.metrics.begin(), c.metrics.end(),
                                  [&](const auto& p) { return p.first == k; });
      std::snprintf(row, sizeof row, "  %*s", static_cast<int>(k.size()),
                    m == c.metrics.end() ? "-" : format_metric(m->second).c_str());
      out += row;
    }
    out += "  " + c.error + "\n";
  }
  std::snprintf(row, sizeof row, "%d done, %d skipped, %d failed%s\n", count(CaptureStatus::Done),
                count(CaptureStatus::Skipped), count(CaptureStatus::Failed),
                cannot_write  ? ", stopped: results cannot be written"
                : interrupted ? ", interrupted"
                              : "");
  return out + row;
}

namespace {

// The `.partial` folder of a capture: its name derives from the capture's, 9 bytes longer.
fs::path partial_dir(const fs::path& out_root, const std::string& name) {
  return out_root / ("." + fitting_name(name, 9) + ".partial");
}

// One capture: run into a temporary folder, mark it, rename it into place.
CaptureOutcome run_capture_once(const ManifestEntry& e, const fs::path& out_root,
                                const CaptureRunner& run_capture,
                                const std::atomic<bool>* cancel) try {
  CaptureOutcome outcome;
  outcome.name = e.name;
  outcome.path = e.path;
  const fs::path final_dir = out_root / e.name;
  if (fs::exists(final_dir / "_DONE")) {
    outcome.status = CaptureStatus::Skipped;
    outcome.metrics = metrics_in(final_dir);
    return outcome;
  }
  const fs::path tmp = partial_dir(out_root, e.name);
  fs::remove_all(tmp);
  std::error_code ec;
  fs::create_directories(tmp, ec);
  if (ec) throw OutputError("cannot create " + tmp.string() + ": " + ec.message());
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<RunResult> result;
  try {
    result = run_capture(e, tmp);
    if (!result->ok()) outcome.error = result->error ? result->error->str() : "failed";
    outcome.cannot_write = result->error && result->error->kind == RunError::Kind::Output;
  } catch (const OutputError& ex) {  // run.json could not be written
    outcome.error = ex.what();
    outcome.cannot_write = true;
  } catch (const std::exception& ex) {
    outcome.error = ex.what();
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bool interrupted = (result && result->status == RunStatus::Interrupted) ||
                           (cancel && cancel->load() && !(result && result->ok()));
  if (interrupted) {
    fs::remove_all(tmp);
    outcome.status = CaptureStatus::Interrupted;
    return outcome;
  }
  if (outcome.cannot_write) {
    // No marker: the capture did not fail, its disk did; a rerun after freeing space redoes it.
    fs::remove_all(tmp);
    outcome.status = CaptureStatus::Failed;
    return outcome;
  }
  json marker = {{"capture", e.name},
                 {"input", e.path},
                 {"finished_at", utc_now_iso8601()},
                 {"seconds", outcome.seconds}};
  if (outcome.error.empty()) {
    outcome.status = CaptureStatus::Done;
    write_file_atomically(tmp / "_DONE", json_text(marker));
  } else {
    outcome.status = CaptureStatus::Failed;
    marker["error"] = outcome.error;
    if (result && result->error) marker["kind"] = to_string(result->error->kind);
    write_file_atomically(tmp / "_FAILED.json", json_text(marker));
  }
  // A failed capture's folder from an earlier run is replaced by this attempt's.
  fs::remove_all(final_dir);
  fs::rename(tmp, final_dir, ec);
  if (ec)
    throw OutputError("cannot rename " + tmp.string() + " to " + final_dir.string() + ": " +
                      ec.message());
  outcome.metrics = metrics_in(final_dir);
  return outcome;
} catch (const OutputError&) {
  // The marker could not be written: no half-finished capture stays behind.
  std::error_code ec;
  fs::remove_all(partial_dir(out_root, e.name), ec);
  throw;
}

// Merges every _summary-<i><suffix> in out_root into _summary.json. The lock makes the list and
// the write one step, so the shard that finishes last cannot be overwritten by an earlier one's
// merge that did not see its file.
void merge_shard_summaries(const fs::path& out_root, const std::string& suffix) {
  const fs::path lock_file = out_root / ".summary.lock";
  const int fd = ::open(lock_file.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot open " + lock_file.string());
  struct Unlock {
    int fd;
    ~Unlock() { ::close(fd); }  // closing releases the flock
  } unlock{fd};
  while (::flock(fd, LOCK_EX) != 0)
    if (errno != EINTR) throw std::runtime_error("cannot lock " + lock_file.string());
  std::vector<json> rows;
  std::vector<int> shards;
  bool interrupted = false;
  for (const auto& entry : fs::directory_iterator(out_root)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("_summary-", 0) != 0 || name.size() <= suffix.size() + 9 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const json part = parse_json_or_discarded(
        std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
    if (part.is_discarded() || !part.contains("captures")) {
      spdlog::warn("{}: not a shard summary, left out of _summary.json", entry.path().string());
      continue;
    }
    shards.push_back(std::stoi(name.substr(9)));
    interrupted |= part.value("interrupted", false);
    for (const auto& row : part["captures"]) rows.push_back(row);
  }
  std::sort(rows.begin(), rows.end(),
            [](const json& a, const json& b) { return a.value("name", "") < b.value("name", ""); });
  std::sort(shards.begin(), shards.end());
  std::map<std::string, int> counts = {{"done", 0}, {"skipped", 0}, {"failed", 0}};
  for (const auto& row : rows) ++counts[row.value("status", "")];
  json merged = {{"captures", rows},
                 {"done", counts["done"]},
                 {"skipped", counts["skipped"]},
                 {"failed", counts["failed"]},
                 {"interrupted", interrupted},
                 {"shards_merged", shards},
                 {"shard_count", std::stoi(suffix.substr(2))}};
  write_file_atomically(out_root / "_summary.json", json_text(merged));
}

}  // namespace

BatchSummary run_batch(const std::vector<ManifestEntry>& manifest, const fs::path& out_root,
                       Shard shard, const CaptureRunner& run_capture,
                       const std::atomic<bool>* cancel) {
  std::error_code ec;
  fs::create_directories(out_root, ec);
  if (ec) throw OutputError("cannot create " + out_root.string() + ": " + ec.message());
  BatchSummary summary;
  for (const auto& e : manifest) {
    if (!shard.takes(e.index)) continue;
    if (cancel && cancel->load()) {
      summary.interrupted = true;
      break;
    }
    spdlog::info("capture {} ({})", e.name, e.path);
    CaptureOutcome outcome;
    try {
      outcome = run_capture_once(e, out_root, run_capture, cancel);
    } catch (const std::exception& ex) {
      // This capture cannot be run (its folder cannot be made or moved, ...): it fails alone;
      // when its results cannot be written (a full disk: its marker, after the child wrote its
      // files) the batch stops below, as the next capture would fail alike.
      outcome.name = e.name;
      outcome.path = e.path;
      outcome.status = CaptureStatus::Failed;
      outcome.error = ex.what();
      outcome.cannot_write = dynamic_cast<const OutputError*>(&ex) != nullptr;
    }
    if (outcome.status == CaptureStatus::Failed)
      spdlog::error("capture {} failed: {}", e.name, outcome.error);
    else
      spdlog::info("capture {}: {}", e.name, to_string(outcome.status));
    const bool stop = outcome.status == CaptureStatus::Interrupted || outcome.cannot_write;
    summary.cannot_write = outcome.cannot_write;
    summary.captures.push_back(std::move(outcome));
    if (stop) {
      summary.interrupted = true;
      break;
    }
  }
  // A disk that filled up may not take the summary either: that is said, and the summary is
  // still returned (and printed by the command line).
  try {
    if (shard.count == 1) {
      write_file_atomically(out_root / "_summary.json", json_text(summary.json()));
    } else {
      const std::string suffix = "of" + std::to_string(shard.count) + ".json";
      write_file_atomically(out_root / ("_summary-" + std::to_string(shard.index) + suffix),
                            json_text(summary.json()));
      merge_shard_summaries(out_root, suffix);
    }
  } catch (const OutputError& e) {
    spdlog::error("{}", e.what());
    summary.cannot_write = true;
  }
  return summary;
}

}  // namespace gslift
