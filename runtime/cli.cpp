// The gslift command line: a visible table of commands, each parsing its own options, then
// load -> validate -> run -> write, with one place that maps failures to exit codes
// (runtime/exit_codes.hpp).
#include "runtime/cli.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <oneapi/tbb/global_control.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "base/input_file.hpp"
#include "graph/loader.hpp"
#include "graph/suggest.hpp"
#include "runtime/batch.hpp"
#include "runtime/executor.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/graph_yaml.hpp"
#include "runtime/node_catalogue.hpp"
#include "runtime/progress.hpp"
#include "runtime/signals.hpp"
#include "runtime/version.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

// A command-line mistake: printed with a pointer to --help, exit code kUsage.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

constexpr const char* kExitCodes =
    "exit codes:\n"
    "  0    success\n"
    "  2    usage error (bad command line)\n"
    "  3    invalid graph (every diagnostic is printed)\n"
    "  4    bad input: a file is missing or unreadable\n"
    "  5    a node failed while running\n"
    "  6    batch: some captures failed, the others are done\n"
    "  70   internal error (a bug)\n"
    "  130  interrupted (SIGINT/SIGTERM)\n";

// The parsed options of one command: --name value / --name=value, repeatable ones collected.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> values;
  std::set<std::string> flags;

  bool has(const std::string& name) const { return values.count(name) != 0; }
  std::string last(const std::string& name, const std::string& fallback = {}) const {
    auto it = values.find(name);
    return it == values.end() ? fallback : it->second.back();
  }
  std::vector<std::string> all(const std::string& name) const {
    auto it = values.find(name);
    return it == values.end() ? std::vector<std::string>{} : it->second;
  }
};

Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& valued,
                const std::vector<std::string>& flag_names) {
  Args args;
  std::vector<std::string> known = valued;
  known.insert(known.end(), flag_names.begin(), flag_names.end());
  for (int i = first; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-h") a = "--help";
    if (a.rfind("--", 0) != 0 || a == "--") {
      args.positional.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name.resize(eq);
    }
    const bool is_valued = std::find(valued.begin(), valued.end(), name) != valued.end();
    const bool is_flag = std::find(flag_names.begin(), flag_names.end(), name) != flag_names.end();
    if (!is_valued && !is_flag) {
      std::vector<std::string> dashed;
      for (const auto& k : known) dashed.push_back("--" + k);
      const std::string hint = suggest("--" + name, dashed);
      throw UsageError("unknown option '--" + name + "'" + (hint.empty() ? "" : " (" + hint + ")"));
    }
    if (is_flag) {
      if (inline_value) throw UsageError("option '--" + name + "' takes no value");
      args.flags.insert(name);
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= argc) throw UsageError("option '--" + name + "' needs a value");
      value = argv[++i];
    }
    args.values[name].push_back(value);
  }
  return args;
}

int64_t parse_integer(const std::string& option, const std::string& text, int64_t min,
                      int64_t max = std::numeric_limits<int64_t>::max()) {
  size_t used = 0;
  int64_t v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || v < min || v > max)
    throw UsageError("--" + option + " expects an integer >= " + std::to_string(min) +
                     (max < std::numeric_limits<int64_t>::max() ? " and <= " + std::to_string(max)
                                                                : std::string()) +
                     ", got '" + text + "'");
  return v;
}

// --threads: 0 = all cores. The ceiling keeps a typo from asking TBB for thousands of threads
// (5000 aborted in pthread_create, 10^7 crashed): far above any machine gslift runs on, and more
// workers than cores only time-slice.
constexpr int64_t kMaxThreads = 1024;

// An output folder that exists as something else (a file, a device) is bad input named by its
// path, before anything runs (it used to end as an internal error when run.json was written).
void check_output_folder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError("--out " + out.string() + " exists and is not a folder");
}

int64_t parse_threads(const Args& args) {
  return parse_integer("threads", args.last("threads", "0"), 0, kMaxThreads);
}

void set_up_logging(const Args& args) {
  if (!spdlog::get("gslift")) spdlog::set_default_logger(spdlog::stderr_color_mt("gslift"));
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
  const std::string level = args.last("log-level", "info");
  static const std::vector<std::string> levels = {"trace", "debug",    "info", "warn",
                                                  "error", "critical", "off"};
  if (std::find(levels.begin(), levels.end(), level) == levels.end()) {
    const std::string hint = suggest(level, levels, true);
    throw UsageError("unknown --log-level '" + level + "' (" + hint + ")");
  }
  spdlog::set_level(spdlog::level::from_str(level));
}

// --input and --seed become graph vars ${input} and ${seed}; --set is passed through.
LoadOptions load_options(const Args& args) {
  LoadOptions opt;
  if (args.has("input")) opt.vars["input"] = args.last("input");
  if (args.has("seed")) {
    parse_integer("seed", args.last("seed"), 0);
    opt.vars["seed"] = args.last("seed");
  }
  opt.sets = args.all("set");
  return opt;
}

void print_diagnostics(const std::vector<Diagnostic>& diagnostics) {
  for (const auto& d : diagnostics) std::fprintf(stderr, "%s\n", d.str().c_str());
}

// Loads and validates; prints every diagnostic; nullopt when the graph is invalid.
std::optional<Graph> load_checked(const std::string& file, const Registry& registry,
                                  const LoadOptions& opt) {
  require_regular_file(file, "graph file");  // a directory, FIFO or symlink loop: exit 4
  LoadResult loaded = load_graph(file, registry, opt);
  print_diagnostics(loaded.diagnostics);
  if (!loaded.ok()) {
    size_t errors = 0;
    for (const auto& d : loaded.diagnostics) errors += d.severity == Diagnostic::Severity::Error;
    std::fprintf(stderr, "%s: invalid graph (%zu error%s)\n", file.c_str(), errors,
                 errors == 1 ? "" : "s");
  }
  return std::move(loaded.graph);
}

// The run seed: the graph's `seed` param (where --seed lands too), else 0.
uint64_t run_seed(const Graph& graph) {
  auto it = graph.params.find("seed");
  if (it == graph.params.end()) return 0;
  if (const int64_t* v = std::get_if<int64_t>(&it->second); v && *v >= 0)
    return static_cast<uint64_t>(*v);
  throw InputError("graph param 'seed' must be a non-negative integer, got " +
                   to_string(it->second));
}

// The options known from the command line alone, checked before the graph is loaded; the seed
// comes from the loaded graph (run_seed).
RunOptions command_line_run_options(const Args& args) {
  RunOptions opt;
  opt.threads = static_cast<int>(parse_threads(args));
  opt.run_input = args.last("input");
  opt.cancel = &interrupt_flag();
  return opt;
}

int exit_code_of(const RunResult& r) {
  if (r.status == RunStatus::Ok) return exit_code::kOk;
  if (r.status == RunStatus::Interrupted) return exit_code::kInterrupted;
  return r.error && r.error->kind == RunError::Kind::BadInput ? exit_code::kBadInput
                                                              : exit_code::kNodeFailed;
}

// "out/demo (run.json, capture/, ...)"
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

struct Command {
  const char* name;
  const char* summary;
  const char* help;
  int (*fn)(int argc, char** argv, const Registry& registry);
};

int cmd_run(int argc, char** argv, const Registry& registry);
int cmd_validate(int argc, char** argv, const Registry& registry);
int cmd_nodes(int argc, char** argv, const Registry& registry);
int cmd_batch(int argc, char** argv, const Registry& registry);

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"run", "run a graph on one capture",
       "usage: gslift run GRAPH [--input PATH] [--set NODE.PARAM=VALUE]... [--out DIR]\n"
       "                        [--threads N] [--seed S] [--log-level L]\n\n"
       "Validates GRAPH, runs it and writes every node's outputs under DIR/<node id>/ and the\n"
       "run record DIR/run.json (also when the run fails).\n\n"
       "options:\n"
       "  --input PATH            the capture to process (graph var ${input})\n"
       "  --set NODE.PARAM=VALUE  override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
       "                          NAME=VALUE sets the graph param NAME\n"
       "  --out DIR               results folder (default out/<graph name>)\n"
       "  --threads N             worker threads, 0 = all cores (default 0, at most 1024)\n"
       "  --seed S                run seed (graph var ${seed}; default: the graph's seed or 0)\n"
       "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n"
       "  -h, --help              this help\n",
       cmd_run},
      {"validate", "check a graph without running it",
       "usage: gslift validate GRAPH [--set NODE.PARAM=VALUE]... [--input PATH] [--seed S]\n"
       "                             [--print]\n\n"
       "Prints every diagnostic (file:line:col) and exits 3 when the graph is invalid.\n\n"
       "options:\n"
       "  --set NODE.PARAM=VALUE  override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
       "                          NAME=VALUE sets the graph param NAME\n"
       "  --input PATH            graph var ${input}\n"
       "  --seed S                graph var ${seed}\n"
       "  --print                 print the resolved graph (defaults filled in) as YAML\n"
       "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n"
       "  -h, --help              this help\n",
       cmd_validate},
      {"nodes", "list node types, or document one",
       "usage: gslift nodes [TYPE]\n\n"
       "Without TYPE: every registered node type with its one-line doc. With TYPE: its input\n"
       "and output ports (type, doc) and params (type, default, range, choices, doc).\n\n"
       "options:\n"
       "  -h, --help              this help\n",
       cmd_nodes},
      {"batch", "run a graph over many captures",
       "usage: gslift batch MANIFEST GRAPH --out DIR [--shard I/N] [--set NODE.PARAM=VALUE]...\n"
       "                    [--threads N] [--seed S] [--log-level L]\n\n"
       "MANIFEST lists one capture path per line ('#' comments; relative paths are relative to\n"
       "the manifest). Each capture's results go to DIR/<capture name>/, written under a\n"
       "temporary name and renamed when finished, with a _DONE marker: a rerun skips finished\n"
       "captures. A failed capture gets _FAILED.json and the others go on. A summary table is\n"
       "printed and written to DIR/_summary.json (_summary-IofN.json with --shard).\n\n"
       "options:\n"
       "  --out DIR               results root (required)\n"
       "  --shard I/N             take the captures whose index % N == I (Slurm/K8s arrays)\n"
       "  --set NODE.PARAM=VALUE  override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
       "                          NAME=VALUE sets the graph param NAME\n"
       "  --threads N             worker threads per capture, 0 = all cores (default 0, at most "
       "1024)\n"
       "  --seed S                run seed (graph var ${seed}); the same for every capture\n"
       "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n"
       "  -h, --help              this help\n",
       cmd_batch},
  };
  return table;
}

void print_command_help(const Command& c) {
  std::printf("%s\n%s", c.help, kExitCodes);
}

void print_global_help(const std::vector<ExtraCommand>& extra) {
  std::printf(
      "gslift %s: posed views of a room -> 3D Gaussian Splatting scene, segmented and "
      "queryable.\n\n"
      "usage: gslift COMMAND [options]    (gslift COMMAND --help for its options)\n\n"
      "commands:\n",
      gslift_version());
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name, c.summary);
  for (const auto& c : extra) std::printf("  %-10s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf(
      "\nglobal options:\n  -h, --help     this help\n  --version      print the version\n\n%s",
      kExitCodes);
}

const Command& command_named(const std::string& name) {
  for (const auto& c : commands())
    if (name == c.name) return c;
  throw std::logic_error("no command " + name);
}

int cmd_run(int argc, char** argv, const Registry& registry) {
  const Args args =
      parse_args(argc, argv, 2, {"input", "set", "out", "threads", "seed", "log-level"}, {"help"});
  if (args.flags.count("help")) return print_command_help(command_named("run")), 0;
  if (args.positional.size() != 1) throw UsageError("run expects one GRAPH file");
  set_up_logging(args);
  RunOptions opt = command_line_run_options(args);
  const auto graph = load_checked(args.positional[0], registry, load_options(args));
  if (!graph) return exit_code::kInvalidGraph;
  opt.seed = run_seed(*graph);
  opt.out_dir = args.last("out", (fs::path("out") / graph->name).string());
  check_output_folder(opt.out_dir);
  ConsoleProgress progress(is_terminal(stderr), stderr);
  opt.progress = &progress;
  install_interrupt_handlers();
  spdlog::info("running {} ({} nodes, threads {}, seed {}) -> {}", graph->name, graph->nodes.size(),
               opt.threads ? std::to_string(opt.threads) : std::string("auto"), opt.seed,
               opt.out_dir.string());
  const RunResult result = execute(*graph, registry, opt);
  if (result.error) std::fprintf(stderr, "error: %s\n", result.error->str().c_str());
  std::printf("%s in %.2f s\nresults: %s\n", to_string(result.status), result.total_s,
              results_line(opt.out_dir).c_str());
  return exit_code_of(result);
}

int cmd_validate(int argc, char** argv, const Registry& registry) {
  const Args args =
      parse_args(argc, argv, 2, {"input", "set", "seed", "log-level"}, {"help", "print"});
  if (args.flags.count("help")) return print_command_help(command_named("validate")), 0;
  if (args.positional.size() != 1) throw UsageError("validate expects one GRAPH file");
  set_up_logging(args);
  const auto graph = load_checked(args.positional[0], registry, load_options(args));
  if (!graph) return exit_code::kInvalidGraph;
  if (args.flags.count("print")) {
    const std::string text = graph_yaml(*graph);
    std::fwrite(text.data(), 1, text.size(), stdout);  // all of it, should it hold a NUL
  } else {
    std::printf("ok: graph '%s' (%zu nodes)\n", graph->name.c_str(), graph->nodes.size());
  }
  return exit_code::kOk;
}

int cmd_nodes(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, {}, {"help"});
  if (args.flags.count("help")) return print_command_help(command_named("nodes")), 0;
  if (args.positional.size() > 1) throw UsageError("nodes expects at most one TYPE");
  if (args.positional.empty()) {
    std::printf("%s", catalogue_text(registry).c_str());
    return exit_code::kOk;
  }
  const std::string& type = args.positional[0];
  const NodeSpec* spec = registry.find(type);
  if (!spec) {
    const std::string hint = suggest(type, registry.types());
    throw UsageError("unknown node type '" + type + "'" + (hint.empty() ? "" : " (" + hint + ")"));
  }
  std::printf("%s", node_type_text(*spec, registry.source(type)).c_str());
  return exit_code::kOk;
}

int cmd_batch(int argc, char** argv, const Registry& registry) {
  const Args args =
      parse_args(argc, argv, 2, {"set", "out", "shard", "threads", "seed", "log-level"}, {"help"});
  if (args.flags.count("help")) return print_command_help(command_named("batch")), 0;
  if (args.positional.size() != 2) throw UsageError("batch expects MANIFEST and GRAPH");
  if (!args.has("out")) throw UsageError("batch needs --out DIR");
  check_output_folder(args.last("out"));
  set_up_logging(args);
  Shard shard;
  try {
    if (args.has("shard")) shard = parse_shard(args.last("shard"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const RunOptions base = command_line_run_options(args);
  const auto manifest = read_manifest(args.positional[0]);
  const std::string graph_file = args.positional[1];
  // Validate once up front (with the shard's first capture as ${input}) so that a broken graph
  // is one error, not one failure per capture.
  for (const auto& e : manifest) {
    if (!shard.takes(e.index)) continue;
    LoadOptions lopt = load_options(args);
    lopt.vars["input"] = e.path;
    if (!load_checked(graph_file, registry, lopt)) return exit_code::kInvalidGraph;
    break;
  }
  install_interrupt_handlers();
  ConsoleProgress progress(is_terminal(stderr), stderr);
  const auto run_capture = [&](const ManifestEntry& e, const fs::path& out) {
    LoadOptions lopt = load_options(args);
    lopt.vars["input"] = e.path;
    LoadResult loaded = load_graph(graph_file, registry, lopt);
    if (!loaded.ok()) {
      std::string text = "invalid graph for this capture:";
      for (const auto& d : loaded.diagnostics) text += "\n" + d.str();
      throw std::runtime_error(text);
    }
    RunOptions opt = base;
    opt.seed = run_seed(*loaded.graph);
    opt.run_input = e.path;
    opt.out_dir = out;
    opt.progress = &progress;
    return execute(*loaded.graph, registry, opt);
  };
  const BatchSummary summary =
      run_batch(manifest, args.last("out"), shard, run_capture, &interrupt_flag());
  std::printf("%s", summary.table().c_str());
  if (summary.interrupted) return exit_code::kInterrupted;
  return summary.count(CaptureStatus::Failed) ? exit_code::kBatchPartial : exit_code::kOk;
}

constexpr const char* kCommonOptions =
    "\noptions gslift takes for this command too:\n"
    "  --threads N             worker threads, 0 = all cores (default 0, at most 1024)\n"
    "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n";

// A command from outside the runtime (gslift synth) takes --threads and --log-level like run and
// batch: they are taken out of its arguments here and applied around it (--threads caps every
// TBB loop, as in execute()); the rest is the command's own.
int run_extra(const ExtraCommand& command, int argc, char** argv) {
  static const std::vector<std::string> common = {"threads", "log-level"};
  std::vector<char*> own = {argv[1]};
  std::vector<char*> taken = {argv[0], argv[1]};
  bool help = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    help |= a == "--help" || a == "-h";
    const bool is_common =
        a.rfind("--", 0) == 0 &&
        std::find(common.begin(), common.end(), a.substr(2, a.find('=') - 2)) != common.end();
    if (!is_common) {
      own.push_back(argv[i]);
      continue;
    }
    taken.push_back(argv[i]);
    if (a.find('=') == std::string::npos && i + 1 < argc) taken.push_back(argv[++i]);
  }
  const Args args = parse_args(int(taken.size()), taken.data(), 2, common, {});
  set_up_logging(args);
  const auto threads = static_cast<size_t>(parse_threads(args));
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
  const int code = command.run(int(own.size()), own.data());
  if (help) std::printf("%s", kCommonOptions);
  return code;
}

int dispatch(int argc, char** argv, const Registry& registry,
             const std::vector<ExtraCommand>& extra) {
  if (argc < 2) {
    print_global_help(extra);
    return exit_code::kUsage;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || first == "help") {
    print_global_help(extra);
    return exit_code::kOk;
  }
  if (first == "--version") {
    std::printf("gslift %s (%s)\n", gslift_version(), gslift_git_version());
    return exit_code::kOk;
  }
  for (const auto& c : commands())
    if (first == c.name) return c.fn(argc, argv, registry);
  for (const auto& c : extra)
    if (first == c.name) return run_extra(c, argc, argv);
  std::vector<std::string> names;
  for (const auto& c : commands()) names.push_back(c.name);
  for (const auto& c : extra) names.push_back(c.name);
  const std::string hint = suggest(first, names, true);
  throw UsageError("unknown command '" + first + "' (" + hint + ")");
}

}  // namespace

int cli_main(int argc, char** argv, const Registry& registry,
             const std::vector<ExtraCommand>& extra) {
  try {
    return dispatch(argc, argv, registry, extra);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "gslift: %s\nsee 'gslift --help'\n", e.what());
    return exit_code::kUsage;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return exit_code::kBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return exit_code::kInternal;
  }
}

}  // namespace gslift
