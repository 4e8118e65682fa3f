// What a node body sees while it runs. A node is a thin adapter: it reads its typed inputs from the
// context, receives its params already read into an options struct (Registry::add with a
// ParamTable: a param is never read by name), calls a plain algorithm, and writes typed outputs
// (and files) back.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include "base/errors.hpp"
#include "graph/graph.hpp"
#include "graph/node_spec.hpp"
#include "runtime/progress.hpp"
#include "runtime/value.hpp"

namespace gslift {

// Thrown (by NodeContext::check_cancelled) when the run was cancelled or interrupted.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

class NodeContext {
 public:
  virtual ~NodeContext() = default;

  const GraphNode& node() const { return *node_; }
  const NodeSpec& spec() const { return *spec_; }

  // Inputs. `input<T>` throws std::logic_error for an unconnected required port (validation makes
  // that impossible in a real run); `has_input` tells whether an optional port is connected.
  bool has_input(const std::string& port) const { return inputs_.count(port) != 0; }
  template <class T>
  std::shared_ptr<const T> input(const std::string& port) const {
    auto it = inputs_.find(port);
    if (it == inputs_.end()) throw std::logic_error("input port '" + port + "' is not connected");
    return it->second.get<T>();
  }

  template <class T>
  void output(const std::string& port, std::shared_ptr<const T> v) {
    set_output(port, Value::of<T>(std::move(v)));
  }
  template <class T>
  void output(const std::string& port, T v) {
    set_output(port, Value::make<T>(std::move(v)));
  }
  virtual void set_output(const std::string& port, Value v) = 0;

  // Seed for this node, derived from (run seed, node id): stable across thread counts and runs.
  uint64_t seed() const { return seed_; }
  // This node's own output folder (<out>/<node id>/), created on first use; empty path when the
  // run writes no files.
  virtual std::filesystem::path out_dir() = 0;
  // The run's input path (--input), may be empty.
  virtual const std::string& run_input() const = 0;

  // Progress for long nodes in [0,1]; cheap, may be called every iteration.
  virtual void progress(double fraction, const std::string& what = {}) = 0;
  // A training loop's step (step / total, loss, train PSNR): the progress line adds the time
  // left. Without a richer sink it is the fraction with the fields as text.
  virtual void progress(const TrainingStep& step) {
    progress(step_fraction(step), training_step_text(step));
  }
  // True once the run is cancelled (another node failed, or SIGINT). Long loops poll it.
  virtual bool cancelled() const = 0;
  void check_cancelled() const {
    if (cancelled()) throw Cancelled();
  }
  // Free-form numbers recorded in run.json under the node (counts, metrics, memory).
  virtual void record(const std::string& key, double value) = 0;
  virtual void record(const std::string& key, const std::string& value) = 0;

 protected:
  const GraphNode* node_ = nullptr;
  const NodeSpec* spec_ = nullptr;
  std::map<std::string, Value> inputs_;
  uint64_t seed_ = 0;
};

using NodeFn = std::function<void(NodeContext&)>;

}  // namespace gslift
