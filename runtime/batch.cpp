#include "runtime/batch.hpp"

#include <chrono>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "base/input_file.hpp"
#include "runtime/atomic_file.hpp"
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
  return name.empty() || name == "." || name == ".." ? "capture" : name;
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

json BatchSummary::json() const {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& c : captures)
    rows.push_back({{"name", c.name},
                    {"path", c.path},
                    {"status", to_string(c.status)},
                    {"seconds", c.seconds},
                    {"error", c.error}});
  return {{"captures", rows},
          {"done", count(CaptureStatus::Done)},
          {"skipped", count(CaptureStatus::Skipped)},
          {"failed", count(CaptureStatus::Failed)},
          {"interrupted", interrupted}};
}

std::string BatchSummary::table() const {
  size_t width = 7;
  for (const auto& c : captures) width = std::max(width, c.name.size());
  std::string out;
  char row[512];
  std::snprintf(row, sizeof row, "%-*s  %-11s  %9s  %s\n", static_cast<int>(width), "capture",
                "status", "seconds", "error");
  out += row;
  for (const auto& c : captures) {
    std::snprintf(row, sizeof row, "%-*s  %-11s  %9.2f  ", static_cast<int>(width), c.name.c_str(),
                  to_string(c.status), c.seconds);
    out += row + c.error + "\n";
  }
  std::snprintf(row, sizeof row, "%d done, %d skipped, %d failed%s\n", count(CaptureStatus::Done),
                count(CaptureStatus::Skipped), count(CaptureStatus::Failed),
                interrupted ? ", interrupted" : "");
  return out + row;
}

namespace {

// One capture: run into a temporary folder, mark it, rename it into place.
CaptureOutcome run_capture_once(const ManifestEntry& e, const fs::path& out_root,
                                const CaptureRunner& run_capture, const std::atomic<bool>* cancel) {
  CaptureOutcome outcome;
  outcome.name = e.name;
  outcome.path = e.path;
  const fs::path final_dir = out_root / e.name;
  if (fs::exists(final_dir / "_DONE")) {
    outcome.status = CaptureStatus::Skipped;
    return outcome;
  }
  const fs::path tmp = out_root / ("." + e.name + ".partial");
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<RunResult> result;
  try {
    result = run_capture(e, tmp);
    if (!result->ok()) outcome.error = result->error ? result->error->str() : "failed";
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
  fs::rename(tmp, final_dir);
  return outcome;
}

}  // namespace

BatchSummary run_batch(const std::vector<ManifestEntry>& manifest, const fs::path& out_root,
                       Shard shard, const CaptureRunner& run_capture,
                       const std::atomic<bool>* cancel) {
  fs::create_directories(out_root);
  BatchSummary summary;
  for (const auto& e : manifest) {
    if (!shard.takes(e.index)) continue;
    if (cancel && cancel->load()) {
      summary.interrupted = true;
      break;
    }
    spdlog::info("capture {} ({})", e.name, e.path);
    CaptureOutcome outcome = run_capture_once(e, out_root, run_capture, cancel);
    if (outcome.status == CaptureStatus::Failed)
      spdlog::error("capture {} failed: {}", e.name, outcome.error);
    else
      spdlog::info("capture {}: {}", e.name, to_string(outcome.status));
    const bool stop = outcome.status == CaptureStatus::Interrupted;
    summary.captures.push_back(std::move(outcome));
    if (stop) {
      summary.interrupted = true;
      break;
    }
  }
  const std::string file = shard.count == 1 ? "_summary.json"
                                            : "_summary-" + std::to_string(shard.index) + "of" +
                                                  std::to_string(shard.count) + ".json";
  write_file_atomically(out_root / file, json_text(summary.json()));
  return summary;
}

}  // namespace gslift
