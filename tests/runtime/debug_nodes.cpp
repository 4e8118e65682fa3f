#include "tests/runtime/debug_nodes.hpp"

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "base/random.hpp"

namespace gslift {
GSLIFT_PORT_TYPE(std::string, "Text");
}

namespace gslift::test {

namespace {
PortSpec number(const std::string& name, bool optional = false) {
  return PortSpec{name, "Number", "a number", optional};
}
double input_or_zero(const NodeContext& ctx, const std::string& port) {
  return ctx.has_input(port) ? ctx.input<Number>(port)->value : 0.0;
}

// Their params, declared like every node's: one table per options struct.
struct ConstantOptions {
  double value = 0.0;
};
struct SleepOptions {
  int ms = 100;
  bool write = false;
};
enum class FailKind { Input, Other };
struct FailOptions {
  FailKind kind = FailKind::Other;
  std::string message = "boom";
};
const EnumNames<FailKind>& fail_kind_names() {
  static const EnumNames<FailKind> names = {{FailKind::Input, "input"}, {FailKind::Other, "other"}};
  return names;
}
}  // namespace

void write(ByteWriter& w, const Number& n) {
  w.put<double>(n.value);
}
void read(ByteReader& r, Number& n) {
  n.value = r.get<double>();
}

Registry debug_registry() {
  Registry r;
  r.add_codec<Number>(1);
  r.add(NodeSpec{"debug.constant", "a constant", {}, {number("out")}},
        ParamTable<ConstantOptions>().add("value", &ConstantOptions::value, "the value"),
        [](NodeContext& ctx, const ConstantOptions& o) { ctx.output("out", Number{o.value}); });
  r.add(
      NodeSpec{
          "debug.sleep", "sleeps, polling cancellation", {number("in", true)}, {number("out")}},
      ParamTable<SleepOptions>()
          .add("ms", &SleepOptions::ms, "milliseconds", 0)
          .add("write", &SleepOptions::write, "write partial.txt into the node folder first"),
      [](NodeContext& ctx, const SleepOptions& o) {
        if (o.write) std::ofstream(ctx.out_dir() / "partial.txt") << "half";
        const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(o.ms);
        // Polls and reports at least once, however late the thread gets here: tests that wait
        // for a node's first progress report, or cancel on it, never depend on timing.
        while (true) {
          ctx.check_cancelled();
          ctx.progress(0.5, "sleeping");
          if (std::chrono::steady_clock::now() >= end) break;
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        ctx.output("out", Number{input_or_zero(ctx, "in")});
      });
  r.add(NodeSpec{"debug.fail", "throws", {number("in", true)}, {number("out")}},
        ParamTable<FailOptions>()
            .add("kind", &FailOptions::kind, fail_kind_names(), "exception kind")
            .add("message", &FailOptions::message, "exception message"),
        [](NodeContext&, const FailOptions& o) {
          if (o.kind == FailKind::Input) throw InputError(o.message);
          throw std::runtime_error(o.message);
        });
  r.add(NodeSpec{"debug.random", "one seeded draw", {}, {number("out")}, {}}, [](NodeContext& ctx) {
    const double draw = RandomStream(ctx.seed()).uniform();
    ctx.record("seed", std::to_string(ctx.seed()));
    ctx.record("draw", draw);
    ctx.output("out", Number{draw});
  });
  r.add(NodeSpec{"debug.add", "a + b", {number("a"), number("b")}, {number("out")}, {}},
        [](NodeContext& ctx) {
          ctx.output("out", Number{ctx.input<Number>("a")->value + ctx.input<Number>("b")->value});
        });
  r.add(NodeSpec{"debug.lazy", "forgets its output", {}, {number("out")}, {}}, [](NodeContext&) {});
  r.add(NodeSpec{"debug.wrong", "mistyped output", {}, {number("out")}, {}},
        [](NodeContext& ctx) { ctx.set_output("out", Value::make<std::string>("text")); });
  r.add(NodeSpec{"debug.write", "writes its input", {}, {number("out")}, {}}, [](NodeContext& ctx) {
    if (ctx.run_input().find("bad") != std::string::npos)
      throw InputError(ctx.run_input() + ": unreadable");
    // The fault hook of the batch isolation test: a library that aborts the process.
    if (ctx.run_input().find("abort") != std::string::npos) std::abort();
    std::ofstream(ctx.out_dir() / "input.txt") << ctx.run_input();
    ctx.output("out", Number{1.0});
  });
  return r;
}

GraphNode debug_node(const Registry& registry, const std::string& id, const std::string& type,
                     std::map<std::string, PortRef> inputs,
                     std::map<std::string, ParamValue> params, int line) {
  GraphNode n;
  n.id = id;
  n.type = type;
  n.inputs = std::move(inputs);
  for (const auto& p : registry.find(type)->params) n.params[p.name] = *p.default_value;
  for (auto& [k, v] : params) n.params[k] = std::move(v);
  n.loc = SourceLoc{"test.yaml", line, 3};
  return n;
}

}  // namespace gslift::test
