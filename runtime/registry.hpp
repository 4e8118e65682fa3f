// The node registry: every node type's contract (NodeSpec) and the function that runs it.
// Built-in nodes are added by one explicit call, register_builtin_nodes (nodes/builtin.hpp), not
// by static initialisers, which a static library would silently drop.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "base/byte_archive.hpp"
#include "graph/node_spec.hpp"
#include "param/param_table.hpp"
#include "runtime/node.hpp"

namespace gslift {

// How values of one port type are written to and read from the stage cache
// (runtime/stage_cache.hpp). `version` names the binary form; it is part of every cache key.
struct PortCodec {
  int version = 0;
  std::function<void(const Value&, ByteWriter&)> write;
  std::function<Value(ByteReader&)> read;
};

class Registry : public NodeCatalog {
 public:
  // Throws std::logic_error on a duplicate type or an inconsistent spec (bad default, etc.).
  // `source` is the file that registers the node (`gslift nodes TYPE` prints it); the default
  // argument takes the caller's file.
  void add(NodeSpec spec, NodeFn fn, const char* source = __builtin_FILE());

  // A node whose params are the fields of `table`: the spec's params are generated from the
  // table with `defaults`' values, and `body(ctx, options)` receives them read into an Options
  // struct, so a param is declared once and never read by name. `spec.params` must be empty.
  template <class Options, class Body>
  void add(NodeSpec spec, const ParamTable<Options>& table, Body body,
           const Options& defaults = Options{}, const char* source = __builtin_FILE()) {
    if (!spec.params.empty())
      throw std::logic_error("node type '" + spec.type + "' declares params beside its table");
    spec.params = table.specs(defaults);
    add(
        std::move(spec),
        [table, defaults, body](NodeContext& ctx) {
          const Options options = table.read(ctx.node().params, defaults);
          body(ctx, options);
        },
        source);
  }

  // The binary form of port type T for the stage cache: `write(ByteWriter&, const T&)` and
  // `read(ByteReader&, T&)`, found by argument-dependent lookup. A type without one (Capture)
  // makes the nodes that output it run every time.
  template <class T>
  void add_codec(int version) {
    PortCodec codec;
    codec.version = version;
    codec.write = [](const Value& v, ByteWriter& w) { write(w, *v.get<T>()); };
    codec.read = [](ByteReader& r) {
      T value;
      read(r, value);
      return Value::make<T>(std::move(value));
    };
    codecs_[PortTypeName<T>::value] = std::move(codec);
  }
  // Null when the type has no binary form.
  const PortCodec* codec(const std::string& port_type) const;

  // How a node type that opens a capture (ingest.capture) tells, from its params alone and
  // before the run, what the capture holds: the preflight (runtime/preflight.hpp) checks the
  // needs its consumers declare (PortSpec::needs) against it. Throws InputError when the capture
  // cannot be opened; reads no image.
  using CaptureProbe = std::function<CaptureInventory(const std::map<std::string, ParamValue>&)>;
  void add_capture_probe(const std::string& type, CaptureProbe probe);
  // Null when `type` opens no capture.
  const CaptureProbe* capture_probe(const std::string& type) const;

  const NodeSpec* find(const std::string& type) const override;
  std::vector<std::string> types() const override;  // sorted
  const NodeFn& body(const std::string& type) const;
  // The file that registers `type`, relative to the repository root.
  const std::string& source(const std::string& type) const;

 private:
  struct Entry {
    NodeSpec spec;
    NodeFn fn;
    std::string source;
  };
  std::map<std::string, Entry> entries_;
  std::map<std::string, PortCodec> codecs_;
  std::map<std::string, CaptureProbe> probes_;
};

}  // namespace gslift
