#include "runtime/executor.hpp"

#include <chrono>
#include <cstdio>
#include <mutex>
#include <set>
#include <stdexcept>

#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>
#include <sys/resource.h>

#include "runtime/node_seed.hpp"
#include "runtime/preflight.hpp"
#include "runtime/run_record.hpp"
#include "runtime/utc_time.hpp"

namespace gslift {

namespace fs = std::filesystem;

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::Ok:
      return "ok";
    case RunStatus::Failed:
      return "failed";
    case RunStatus::Interrupted:
      return "interrupted";
    case RunStatus::Running:
      return "running";
  }
  return "?";
}

const char* to_string(NodeStatus s) {
  switch (s) {
    case NodeStatus::Pending:
      return "pending";
    case NodeStatus::Ok:
      return "ok";
    case NodeStatus::Failed:
      return "failed";
    case NodeStatus::Cancelled:
      return "cancelled";
  }
  return "?";
}

const char* to_string(RunError::Kind k) {
  switch (k) {
    case RunError::Kind::BadInput:
      return "bad-input";
    case RunError::Kind::NodeFailed:
      return "node-failed";
    case RunError::Kind::Cancelled:
      return "cancelled";
    case RunError::Kind::Output:
      return "output";
  }
  return "?";
}

std::string RunError::str() const {
  if (node.empty()) return message;
  const std::string where = loc.file.empty() ? std::string() : loc.str() + ": ";
  return where + "node '" + node + "' (" + type + ") failed: " + message;
}

const NodeRecord* RunResult::node(const std::string& id) const {
  for (const auto& n : nodes)
    if (n.id == id) return &n;
  return nullptr;
}

namespace {

// This process's own peak resident memory in kB: the high-water mark of its address space
// (VmHWM, proc(5)). Not getrusage's ru_maxrss: exec carries the replaced address space's peak into
// it, and a child that `gslift sweep` or `gslift batch` spawns (posix_spawn shares the parent's
// address space until exec) would report the parent's peak, 2 GB for a graph that needs 85 MB.
// ru_maxrss only where /proc is absent.
int64_t peak_rss_kb() {
  if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    long long kb = -1;
    while (kb < 0 && std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "VmHWM: %lld kB", &kb) != 1) kb = -1;
    std::fclose(f);
    if (kb >= 0) return kb;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;  // kilobytes on Linux
}

// The NodeContext a node body runs with: its inputs, params (on the GraphNode), seed, output
// folder, and the run's shared cancellation state. A body may call it from inside its own
// parallel loops, so the mutable parts are locked.
class RunningNode final : public NodeContext {
 public:
  RunningNode(const GraphNode& node, const NodeSpec& spec, std::map<std::string, Value> inputs,
              const RunOptions& options, const std::atomic<bool>& stopping, NodeRecord& record)
      : options_(options), stopping_(stopping), record_(record) {
    node_ = &node;
    spec_ = &spec;
    inputs_ = std::move(inputs);
    seed_ = node_seed(options.seed, node.id);
  }

  void set_output(const std::string& port, Value v) override {
    const PortSpec* out = spec().find_output(port);
    if (!out)
      throw std::logic_error("node '" + node().id + "' (" + node().type + ") has no output port '" +
                             port + "'");
    if (v.empty() || v.type_name() != out->type)
      throw std::logic_error("node '" + node().id + "' (" + node().type + "): output port '" +
                             port + "' is declared " + out->type + " but was given " +
                             (v.empty() ? std::string("nothing") : v.type_name()));
    std::lock_guard<std::mutex> lock(mutex_);
    outputs_[port] = std::move(v);
  }

  fs::path out_dir() override {
    if (options_.out_dir.empty()) return {};
    const fs::path dir = options_.out_dir / node().id;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!out_dir_created_) {
      std::error_code ec;
      fs::create_directories(dir, ec);
      if (ec) throw OutputError("cannot create folder " + dir.string() + ": " + ec.message());
      out_dir_created_ = true;
    }
    return dir;
  }

  const std::string& run_input() const override { return options_.run_input; }

  void progress(double fraction, const std::string& what) override {
    if (options_.progress) options_.progress->node_progress(node().id, fraction, what);
  }

  void progress(const TrainingStep& step) override {
    if (options_.progress) options_.progress->node_step(node().id, step);
  }

  bool cancelled() const override {
    return stopping_.load(std::memory_order_relaxed) ||
           (options_.cancel && options_.cancel->load(std::memory_order_relaxed));
  }

  void record(const std::string& key, double value) override {
    std::lock_guard<std::mutex> lock(mutex_);
    record_.records[key] = value;
  }
  void record(const std::string& key, const std::string& value) override {
    std::lock_guard<std::mutex> lock(mutex_);
    record_.records[key] = value;
  }

  // The first declared output the body did not set, or nullptr.
  const PortSpec* missing_output() const {
    for (const auto& p : spec().outputs)
      if (!outputs_.count(p.name)) return &p;
    return nullptr;
  }
  std::map<std::string, Value>& outputs() { return outputs_; }

 private:
  const RunOptions& options_;
  const std::atomic<bool>& stopping_;
  NodeRecord& record_;
  std::mutex mutex_;
  std::map<std::string, Value> outputs_;
  bool out_dir_created_ = false;
};

// Shared state of one execution; run_node is the body of every flow-graph node.
class Execution {
 public:
  Execution(const Graph& graph, const Registry& registry, const RunOptions& options,
            RunResult& result)
      : graph_(graph),
        registry_(registry),
        options_(options),
        result_(result),
        outputs_(graph.nodes.size()),
        keys_(graph.nodes.size()),
        t0_(std::chrono::steady_clock::now()) {
    for (size_t i = 0; i < graph.nodes.size(); ++i) index_[graph.nodes[i].id] = i;
  }

  size_t index_of(const std::string& id) const {
    auto it = index_.find(id);
    if (it == index_.end()) throw std::logic_error("graph has no node '" + id + "'");
    return it->second;
  }

  bool interrupted() const { return options_.cancel && options_.cancel->load(); }

  void run_node(size_t i, tbb::task_group_context& group) {
    const GraphNode& gn = graph_.nodes[i];
    NodeRecord& rec = result_.nodes[i];
    // Nothing downstream of a failure (or after an interruption) starts; it stays "pending".
    if (stopping_.load() || interrupted()) return;
    rec.start_s = seconds();
    if (options_.progress) options_.progress->node_started(gn.id, gn.type);
    try {
      const NodeSpec* spec = registry_.find(gn.type);
      if (!spec) throw std::logic_error("node type '" + gn.type + "' is not registered");
      std::map<std::string, Value> inputs;
      for (const auto& [port, ref] : gn.inputs)
        inputs[port] = outputs_[index_of(ref.node)].at(ref.port);
      const std::optional<StageKey> key = cache_key(gn, *spec);
      if (key) rec.cache_key = key->hash;
      const bool cacheable = key && stands_in(*spec);
      const fs::path files =
          options_.out_dir.empty() ? fs::path() : fs::path(options_.out_dir / gn.id);
      if (cacheable) {
        if (auto hit = options_.cache->load(*key, registry_, files)) {
          rec.records = std::move(hit->records);
          rec.cache = "hit";
          rec.status = NodeStatus::Ok;
          outputs_[i] = std::move(hit->outputs);
          finish(i);
          return;
        }
      }
      const FolderSnapshot before = cacheable ? snapshot_files(files) : FolderSnapshot();
      RunningNode ctx(gn, *spec, std::move(inputs), options_, stopping_, rec);
      registry_.body(gn.type)(ctx);
      if (const PortSpec* p = ctx.missing_output())
        throw std::logic_error("node '" + gn.id + "' (" + gn.type +
                               ") did not set its output port '" + p->name + "'");
      if (stopping_.load()) {
        // A failure elsewhere may have cut this node's inner parallel loops short (they share the
        // cancelled task group), so its outputs are not trusted.
        rec.status = NodeStatus::Cancelled;
        rec.error = "cancelled";
      } else {
        rec.status = NodeStatus::Ok;
        outputs_[i] = std::move(ctx.outputs());
        if (cacheable) {
          options_.cache->store(
              *key, registry_, outputs_[i], rec.records, files,
              files.empty() ? std::vector<fs::path>() : files_written(files, before));
          rec.cache = "miss";
        }
      }
    } catch (const Cancelled&) {
      if (stopping_.load() || interrupted()) {
        rec.status = NodeStatus::Cancelled;
        rec.error = "cancelled";
      } else {
        fail(i, RunError::Kind::NodeFailed, "threw Cancelled although the run was not cancelled",
             group);
      }
    } catch (const InputError& e) {
      fail(i, RunError::Kind::BadInput, e.what(), group);
    } catch (const OutputError& e) {
      fail(i, RunError::Kind::Output, e.what(), group);
    } catch (const std::exception& e) {
      fail(i, RunError::Kind::NodeFailed, e.what(), group);
    } catch (...) {
      fail(i, RunError::Kind::NodeFailed, "unknown exception", group);
    }
    finish(i);
  }

  void finish(size_t i) {
    NodeRecord& rec = result_.nodes[i];
    rec.end_s = seconds();
    rec.peak_rss_kb = peak_rss_kb();
    if (options_.progress)
      options_.progress->node_finished(rec.id, to_string(rec.status), rec.end_s - rec.start_s);
  }

  // The node's stage-cache key (also computed for nodes the cache never stands in for: their
  // consumers' keys name it), or nothing when the run has no cache.
  std::optional<StageKey> cache_key(const GraphNode& gn, const NodeSpec& spec) {
    if (!options_.cache) return std::nullopt;
    std::map<std::string, std::string> input_keys;
    for (const auto& [port, ref] : gn.inputs)
      input_keys[port] = keys_[index_of(ref.node)] + "." + ref.port;
    StageKey key = stage_key(gn, spec, registry_, node_seed(options_.seed, gn.id),
                             options_.run_input, input_keys);
    keys_[index_of(gn.id)] = key.hash;
    return key;
  }

  // Whether a cache entry can stand in for running the node: every output has a binary form.
  bool stands_in(const NodeSpec& spec) const {
    if (!spec.cacheable) return false;
    for (const auto& out : spec.outputs)
      if (!registry_.codec(out.type)) return false;
    return true;
  }

  std::optional<RunError> first_error() {
    std::lock_guard<std::mutex> lock(mutex_);
    return first_error_;
  }
  std::vector<std::map<std::string, Value>>& outputs() { return outputs_; }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

 private:
  void fail(size_t i, RunError::Kind kind, const std::string& message,
            tbb::task_group_context& group) {
    const GraphNode& gn = graph_.nodes[i];
    result_.nodes[i].status = NodeStatus::Failed;
    result_.nodes[i].error = message;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!first_error_) first_error_ = RunError{kind, gn.id, gn.type, gn.loc, message};
    }
    stopping_.store(true);
    group.cancel_group_execution();
  }

  const Graph& graph_;
  const Registry& registry_;
  const RunOptions& options_;
  RunResult& result_;
  std::map<std::string, size_t> index_;
  // outputs_[i] is written only by node i and read only by its consumers, which the flow graph
  // starts after node i finished, so no lock is needed.
  std::vector<std::map<std::string, Value>> outputs_;
  std::vector<std::string> keys_;  // stage-cache key hashes, written and read like outputs_
  std::atomic<bool> stopping_{false};
  std::mutex mutex_;
  std::optional<RunError> first_error_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

RunResult execute(const Graph& graph, const Registry& registry, const RunOptions& options) {
  RunResult result;
  result.started_at = utc_now_iso8601();
  result.seed = options.seed;
  result.threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  for (const auto& n : graph.nodes) {
    NodeRecord rec;
    rec.id = n.id;
    rec.type = n.type;
    result.nodes.push_back(std::move(rec));
  }

  if (!options.out_dir.empty()) {
    // Before anything else is written: an earlier run's record in the same folder (status ok,
    // other params) must not stand beside this run's files should this one die before its end.
    result.status = RunStatus::Running;
    write_run_record(options.out_dir / "run.json", graph, result);
    result.status = RunStatus::Ok;
  }
  if (options.preflight) {
    // What the nodes need of the capture, before any of them runs (runtime/preflight.hpp).
    try {
      check_preflight(graph, registry);
    } catch (const InputError& e) {
      result.status = RunStatus::Failed;
      result.error = RunError{RunError::Kind::BadInput, {}, {}, {}, e.what()};
      if (!options.out_dir.empty()) write_run_record(options.out_dir / "run.json", graph, result);
      return result;
    }
  }
  Execution run(graph, registry, options, result);
  {
    // --threads caps every TBB loop inside the nodes too, not only the graph's own tasks.
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<size_t>(result.threads));
    tbb::task_arena arena(result.threads);
    arena.execute([&] {
      tbb::task_group_context group;
      tbb::flow::graph g(group);
      using Step = tbb::flow::continue_node<tbb::flow::continue_msg>;
      tbb::flow::broadcast_node<tbb::flow::continue_msg> start(g);
      std::vector<std::unique_ptr<Step>> steps;
      for (size_t i = 0; i < graph.nodes.size(); ++i)
        steps.push_back(std::make_unique<Step>(
            g, [&run, &group, i](const tbb::flow::continue_msg&) { run.run_node(i, group); }));
      for (size_t i = 0; i < graph.nodes.size(); ++i) {
        // One edge per producer: a continue_node fires after one message per predecessor edge.
        std::set<size_t> producers;
        for (const auto& [port, ref] : graph.nodes[i].inputs)
          producers.insert(run.index_of(ref.node));
        if (producers.empty()) tbb::flow::make_edge(start, *steps[i]);
        for (size_t p : producers) tbb::flow::make_edge(*steps[p], *steps[i]);
      }
      start.try_put(tbb::flow::continue_msg());
      g.wait_for_all();
    });
  }

  result.total_s = run.seconds();
  result.peak_rss_kb = peak_rss_kb();
  result.error = run.first_error();
  bool all_ran = true;
  for (const auto& n : result.nodes) all_ran = all_ran && n.status == NodeStatus::Ok;
  if (result.error) {
    result.status = RunStatus::Failed;
  } else if (!all_ran) {
    result.status = RunStatus::Interrupted;
    result.error = RunError{RunError::Kind::Cancelled, {}, {}, {}, "interrupted"};
  }
  // Outputs of the nodes that finished, also after a failure (useful when debugging a graph).
  for (size_t i = 0; i < graph.nodes.size(); ++i)
    for (auto& [port, value] : run.outputs()[i])
      result.values[graph.nodes[i].id + "." + port] = value;
  if (!options.out_dir.empty()) {
    // A cancelled node stopped halfway: whatever it wrote is incomplete (exit_codes.hpp: "partial
    // outputs removed"). A failed node's files stay, for debugging.
    for (const auto& n : result.nodes)
      if (n.status == NodeStatus::Cancelled) fs::remove_all(options.out_dir / n.id);
    write_run_record(options.out_dir / "run.json", graph, result);
  }
  return result;
}

}  // namespace gslift
