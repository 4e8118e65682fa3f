// The gslift command line: a visible table of commands, each parsing its own options, then
// load -> validate -> run -> write, with one place that maps failures to exit codes
// (runtime/exit_codes.hpp).
#include "runtime/cli.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <oneapi/tbb/global_control.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "base/utf8.hpp"
#include "graph/loader.hpp"
#include "graph/suggest.hpp"
#include "report/report_page.hpp"
#include "report/run_diff.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/batch.hpp"
#include "runtime/child_process.hpp"
#include "runtime/executor.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/graph_yaml.hpp"
#include "runtime/node_catalogue.hpp"
#include "runtime/preflight.hpp"
#include "runtime/progress.hpp"
#include "runtime/run_record.hpp"
#include "runtime/signals.hpp"
#include "runtime/sweep.hpp"
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
    "  1    diff: the runs differ\n"
    "  2    usage error (bad command line)\n"
    "  3    invalid graph (every diagnostic is printed)\n"
    "  4    bad input: a file is missing or unreadable\n"
    "  5    a node failed while running\n"
    "  6    batch: some captures failed, the others are done; sweep: some runs failed\n"
    "  70   internal error (a bug)\n"
    "  73   cannot write the results: disk full, read-only or unwritable folder (path named)\n"
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
  // Created (and its writability tried) before anything runs: a read-only or unwritable folder
  // is one clear error, not a run that fails at its first output.
  fs::create_directories(out, ec);
  if (ec) throw OutputError("cannot create --out " + out.string() + ": " + ec.message());
  if (::access(out.c_str(), W_OK | X_OK) != 0)
    throw OutputError("cannot write in --out " + out.string() + ": " + std::strerror(errno));
}

// `gslift run --out`: gslift writes run.json and node folders into it and removes its own stale
// temporaries there, so it must be a results folder: new, empty, or holding a run.json (an
// earlier run's). Anything else (`--out /`, a home folder, a typo naming a project) is refused
// before a file is written. A folder holding only gslift.log is one a sweep or batch made for
// this run (the child's log is opened before it starts).
void check_results_folder(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out / "run.json", ec)) return;
  for (auto it = fs::directory_iterator(out, ec); !ec && it != fs::directory_iterator();
       it.increment(ec))
    if (it->path().filename() != "gslift.log")
      throw InputError("--out " + out.string() +
                       " is not empty and holds no run.json: not a gslift results folder (name a "
                       "new or empty folder)");
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
  for (const auto& d : diagnostics) std::fprintf(stderr, "%s\n", terminal_safe(d.str()).c_str());
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

// The stage cache of run, batch and sweep (runtime/stage_cache.hpp): on unless --no-cache, in
// --cache-dir (default: the user's cache folder), capped at --cache-size GB (0 = no cap). A
// default folder that cannot be made only costs the cache (a warning); one the user named is
// bad input.
std::unique_ptr<StageCache> command_line_cache(const Args& args) {
  if (args.flags.count("no-cache")) return nullptr;
  const int64_t gb = parse_integer("cache-size", args.last("cache-size", "10"), 0, 1 << 20);
  const bool named = args.has("cache-dir");
  const fs::path dir = named ? fs::path(args.last("cache-dir")) : default_cache_dir();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) {
    if (named) throw InputError("--cache-dir " + dir.string() + " is not a folder gslift can make");
    spdlog::warn("stage cache folder {} cannot be made: running without the cache", dir.string());
    return nullptr;
  }
  return std::make_unique<StageCache>(dir, static_cast<uint64_t>(gb) << 30);
}

// "13 nodes, 9 loaded from the cache" for the closing line.
std::string cache_summary(const RunResult& r) {
  int hits = 0;
  for (const auto& n : r.nodes) hits += n.cache == "hit";
  return hits ? " (" + std::to_string(hits) + " of " + std::to_string(r.nodes.size()) +
                    " nodes loaded from the stage cache)"
              : std::string();
}

int exit_code_of(const RunResult& r) {
  if (r.status == RunStatus::Ok) return exit_code::kOk;
  if (r.status == RunStatus::Interrupted) return exit_code::kInterrupted;
  if (r.error && r.error->kind == RunError::Kind::Output) return exit_code::kCannotWrite;
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
int cmd_sweep(int argc, char** argv, const Registry& registry);
int cmd_report(int argc, char** argv, const Registry& registry);
int cmd_diff(int argc, char** argv, const Registry& registry);

const std::vector<Command>& commands() {
  static const std::vector<Command> table = {
      {"run", "run a graph on one capture",
       "usage: gslift run GRAPH [--input PATH] [--set NODE.PARAM=VALUE]... [--out DIR]\n"
       "                        [--threads N] [--seed S] [--log-level L]\n"
       "                        [--cache-dir DIR] [--cache-size GB] [--no-cache]\n\n"
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
       "  --cache-dir DIR         stage cache folder (default $GSLIFT_STAGE_CACHE, else\n"
       "                          ~/.cache/gslift/stages; $GSLIFT_CACHE or $XDG_CACHE_HOME\n"
       "                          move ~/.cache/gslift)\n"
       "  --cache-size GB         cap of the cache folder, least recently used entries go first\n"
       "                          (default 10, 0 = no cap)\n"
       "  --no-cache              run every node; read and write no cache\n"
       "  -h, --help              this help\n\n"
       "A node whose type, params, input files, seed and inputs match an earlier run is loaded\n"
       "from the stage cache instead of run (run.json says \"cache\": \"hit\").\n",
       cmd_run},
      {"validate", "check a graph without running it",
       "usage: gslift validate GRAPH [--set NODE.PARAM=VALUE]... [--input PATH] [--seed S]\n"
       "                             [--print]\n\n"
       "Prints every diagnostic (file:line:col) and exits 3 when the graph is invalid.\n\n"
       "options:\n"
       "  --set NODE.PARAM=VALUE  override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
       "                          NAME=VALUE sets the graph param NAME\n"
       "  --input PATH            graph var ${input}; the capture is opened and checked for what\n"
       "                          every node needs of it (exit 4 naming each missing thing)\n"
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
       "                    [--threads N] [--seed S] [--log-level L]\n"
       "       gslift batch --discover DIR GRAPH --out OUT [options as above]\n\n"
       "MANIFEST lists one capture path per line ('#' comments; relative paths are relative to\n"
       "the manifest). Each capture's results go to DIR/<capture name>/, written under a\n"
       "temporary name and renamed when finished, with a _DONE marker: a rerun skips finished\n"
       "captures. A failed capture gets _FAILED.json and the others go on. A summary table is\n"
       "printed and written to DIR/_summary.json (with shards, each writes _summary-IofN.json and\n"
       "_summary.json merges those present). docs/batch-cluster.md: Slurm, Kubernetes, nightly.\n\n"
       "options:\n"
       "  --out DIR               results root (required)\n"
       "  --discover DIR          the captures are DIR's subfolders without OUT/<name>/_DONE\n"
       "                          (names starting with '.' or '_' are left out)\n"
       "  --shard I/N             take the captures whose index % N == I; without it, from\n"
       "                          SLURM_ARRAY_TASK_ID/_MIN/_COUNT or JOB_COMPLETION_INDEX\n"
       "  --shard-count N         the shard count with JOB_COMPLETION_INDEX (Kubernetes Indexed\n"
       "                          Job completions; or set GSLIFT_SHARD_COUNT)\n"
       "  --set NODE.PARAM=VALUE  override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
       "                          NAME=VALUE sets the graph param NAME\n"
       "  --threads N             worker threads per capture, 0 = all cores (default 0, at most "
       "1024)\n"
       "  --seed S                run seed (graph var ${seed}); the same for every capture\n"
       "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n"
       "  --cache-dir DIR         stage cache folder (default $GSLIFT_STAGE_CACHE, else\n"
       "                          ~/.cache/gslift/stages; $GSLIFT_CACHE or $XDG_CACHE_HOME\n"
       "                          move ~/.cache/gslift)\n"
       "  --cache-size GB         cap of the cache folder, least recently used entries go first\n"
       "                          (default 10, 0 = no cap)\n"
       "  --no-cache              run every node; read and write no cache\n"
       "  -h, --help              this help\n",
       cmd_batch},
      {"sweep", "run a graph over a grid of params and seeds",
       "usage: gslift sweep GRAPH --grid NODE.PARAM=V1,V2,... [--grid ...] [--seeds 0-4]\n"
       "                    --out DIR [--input PATH] [--set NODE.PARAM=VALUE]... [--threads N]\n"
       "                    [--log-level L] [--cache-dir DIR] [--cache-size GB] [--no-cache]\n\n"
       "Runs GRAPH once per combination of the --grid values (the cartesian product) and seed,\n"
       "each as a `gslift run` of its own in DIR/runs/NNNN/ (its output in gslift.log there)\n"
       "through the stage cache (a changed downstream param reuses everything upstream). Every\n"
       "combination is validated before the first run. DIR/sweep.json, DIR/results.csv (a row\n"
       "per run: params, seed, status, error, time, peak memory, every numeric record as\n"
       "node.key, wall time per node) and DIR/summary.csv (mean and std over seeds) are\n"
       "rewritten after every run, so an interrupted sweep keeps what finished. A failed run is\n"
       "a row with its error; the sweep goes on. gslift report DIR draws it.\n\n"
       "options:\n"
       "  --grid NODE.PARAM=V,... the values of one param (repeatable); commas inside [] or\n"
       "                          quotes belong to a value; NODE.type=A,B swaps stages\n"
       "  --seeds LIST            0-4, 0,2,7 or 3 (default: the graph's seed)\n"
       "  --out DIR               sweep folder (required)\n"
       "  --input PATH            the capture (graph var ${input})\n"
       "  --set NODE.PARAM=VALUE  a param fixed for every run (repeatable)\n"
       "                          ({seed} in --input, --set and --grid values is the run's seed:\n"
       "                          --input 'embedded:or?seed={seed}' varies the capture too)\n"
       "  --threads N             worker threads per run, 0 = all cores (default 0, at most "
       "1024)\n"
       "  --log-level L           trace, debug, info, warn, error, critical, off (default info)\n"
       "  --cache-dir DIR         stage cache folder (as gslift run)\n"
       "  --cache-size GB         cap of the cache folder (default 10, 0 = no cap)\n"
       "  --no-cache              every run runs every node\n"
       "  -h, --help              this help\n\n"
       "Exit code 6 when some runs failed (the table has them), 130 when interrupted.\n",
       cmd_sweep},
      {"report", "write report.html for a run or sweep folder",
       "usage: gslift report DIR [--max-picture-mb N]\n\n"
       "Writes DIR/report.html, one self-contained page (pictures embedded, charts as SVG, no\n"
       "external links). For a run folder (run.json): the graph, a timeline of the nodes, each\n"
       "node's time, memory and records, and every picture the run wrote. For a sweep folder\n"
       "(sweep.json): the summary table, each metric against time, memory and every varied\n"
       "param, and a section per run; each run's own report.html is written too, with its\n"
       "pictures linked (gslift report RUN_DIR embeds them).\n\n"
       "options:\n"
       "  --max-picture-mb N      embed pictures until their files add up to N MB; the rest are\n"
       "                          listed with links (default 32)\n"
       "  -h, --help              this help\n",
       cmd_report},
      {"diff", "print the params, records and graph changes between two runs",
       "usage: gslift diff RUN_A RUN_B\n\n"
       "Reads both run.json files and prints what differs: status, graph structure (nodes added,\n"
       "removed, retyped, rewired; graph params), params per node and records per node (numbers\n"
       "with both values, the delta and the relative change). Time, memory and cache state are\n"
       "printed apart and do not count. Exits 0 when nothing counted differs, 1 when something\n"
       "does (like diff(1)), 4 when a folder is not a readable run.\n\n"
       "options:\n"
       "  -h, --help              this help\n",
       cmd_diff},
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
      parse_args(argc, argv, 2,
                 {"input", "set", "out", "threads", "seed", "log-level", "cache-dir", "cache-size"},
                 {"help", "no-cache"});
  if (args.flags.count("help")) return print_command_help(command_named("run")), 0;
  if (args.positional.size() != 1) throw UsageError("run expects one GRAPH file");
  set_up_logging(args);
  RunOptions opt = command_line_run_options(args);
  const auto graph = load_checked(args.positional[0], registry, load_options(args));
  if (!graph) return exit_code::kInvalidGraph;
  opt.seed = run_seed(*graph);
  opt.out_dir = args.last("out", (fs::path("out") / graph->name).string());
  check_output_folder(opt.out_dir);
  check_results_folder(opt.out_dir);
  const auto cache = command_line_cache(args);
  opt.cache = cache.get();
  std::vector<std::string> node_folders;
  for (const auto& n : graph->nodes) node_folders.push_back(n.id);
  if (const size_t stale = remove_stale_temporaries(opt.out_dir, node_folders))
    spdlog::info("removed {} unfinished file(s) left in {} by a killed run", stale,
                 opt.out_dir.string());
  ConsoleProgress progress(is_terminal(stderr), stderr);
  opt.progress = &progress;
  install_interrupt_handlers();
  spdlog::info("running {} ({} nodes, threads {}, seed {}) -> {}", graph->name, graph->nodes.size(),
               opt.threads ? std::to_string(opt.threads) : std::string("auto"), opt.seed,
               opt.out_dir.string());
  const RunResult result = execute(*graph, registry, opt);
  if (result.error) std::fprintf(stderr, "error: %s\n", terminal_safe(result.error->str()).c_str());
  std::printf("%s in %.2f s%s\nresults: %s\n", to_string(result.status), result.total_s,
              cache_summary(result).c_str(), results_line(opt.out_dir).c_str());
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
  if (args.has("input")) check_preflight(*graph, registry);  // the capture and what it lacks
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

// The command line of a `gslift run` child of batch or sweep, which run each capture or point as
// its own process (runtime/child_process.hpp): `graph_file` into `out` with the parent's thread
// count and cache options, logging at `log_level`; the caller adds --input, --seed and --set.
std::vector<std::string> child_run_command(const Args& args, const std::string& graph_file,
                                           const fs::path& out, const std::string& log_level) {
  std::vector<std::string> child = {fs::read_symlink("/proc/self/exe").string(),
                                    "run",
                                    graph_file,
                                    "--out",
                                    out.string(),
                                    "--threads",
                                    std::to_string(parse_threads(args)),
                                    "--log-level",
                                    log_level};
  for (const char* opt : {"cache-dir", "cache-size"})
    if (args.has(opt)) child.insert(child.end(), {std::string("--") + opt, args.last(opt)});
  if (args.flags.count("no-cache")) child.push_back("--no-cache");
  return child;
}

int cmd_batch(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2,
                               {"set", "out", "shard", "shard-count", "discover", "threads", "seed",
                                "log-level", "cache-dir", "cache-size"},
                               {"help", "no-cache"});
  if (args.flags.count("help")) return print_command_help(command_named("batch")), 0;
  const bool discover = args.has("discover");
  if (args.positional.size() != (discover ? 1u : 2u))
    throw UsageError(discover ? "batch --discover DIR expects GRAPH only"
                              : "batch expects MANIFEST and GRAPH");
  if (!args.has("out")) throw UsageError("batch needs --out DIR");
  set_up_logging(args);
  Shard shard;
  try {
    std::optional<int> shard_count;
    if (args.has("shard-count"))
      shard_count = static_cast<int>(parse_integer("shard-count", args.last("shard-count"), 1,
                                                   std::numeric_limits<int>::max()));
    if (args.has("shard")) {
      shard = parse_shard(args.last("shard"));
    } else if (const auto from_env = shard_from_environment(
                   [](const std::string& name) -> std::optional<std::string> {
                     const char* v = std::getenv(name.c_str());
                     return v ? std::optional<std::string>(v) : std::nullopt;
                   },
                   shard_count)) {
      shard = from_env->shard;
      spdlog::info("shard {}/{} from {}", shard.index, shard.count, from_env->source);
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  parse_threads(args);
  check_output_folder(args.last("out"));
  command_line_cache(args);  // a bad --cache-dir is one error here, not one per capture
  const auto manifest = discover ? discover_captures(args.last("discover"), args.last("out"))
                                 : read_manifest(args.positional[0]);
  const std::string graph_file = args.positional[discover ? 0 : 1];
  if (discover)
    spdlog::info("discovered {} capture(s) without a result under {}", manifest.size(),
                 args.last("discover"));
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
  const auto run_capture = [&](const ManifestEntry& e, const fs::path& out) {
    // The capture's log (its gslift.log) at the batch's level: a nightly log keeps each
    // capture's progress, as when the batch ran them in its own process.
    std::vector<std::string> child =
        child_run_command(args, graph_file, out, args.last("log-level", "info"));
    child.insert(child.end(), {"--input", e.path});
    if (args.has("seed")) child.insert(child.end(), {"--seed", args.last("seed")});
    for (const auto& s : args.all("set")) child.insert(child.end(), {"--set", s});
    const fs::path log = out / "gslift.log";
    return child_run_result(run_child_process(child, log.string(), &interrupt_flag()), out, log);
  };
  const BatchSummary summary =
      run_batch(manifest, args.last("out"), shard, run_capture, &interrupt_flag());
  std::printf("%s", summary.table().c_str());
  if (summary.cannot_write) return exit_code::kCannotWrite;
  if (summary.interrupted) return exit_code::kInterrupted;
  return summary.count(CaptureStatus::Failed) ? exit_code::kBatchPartial : exit_code::kOk;
}

// The headline metrics of a run for the sweep table: the evaluation nodes' numeric records,
// without per-class entries ("IoU/table"), at most five.
std::vector<std::string> headline_metrics(const nlohmann::json& run_json) {
  std::vector<std::string> keys;
  for (const auto& n : run_json.at("nodes")) {
    if (n.at("type").get<std::string>().rfind("eval.", 0) != 0) continue;
    for (const auto& [key, value] : n.at("records").items())
      if (value.is_number() && key.find('/') == std::string::npos && keys.size() < 5)
        keys.push_back(n.at("id").get<std::string>() + "." + key);
  }
  return keys;
}

int cmd_sweep(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(
      argc, argv, 2,
      {"grid", "seeds", "out", "input", "set", "threads", "log-level", "cache-dir", "cache-size"},
      {"help", "no-cache"});
  if (args.flags.count("help")) return print_command_help(command_named("sweep")), 0;
  if (args.positional.size() != 1) throw UsageError("sweep expects one GRAPH file");
  if (!args.has("out")) throw UsageError("sweep needs --out DIR");
  if (!args.has("grid")) throw UsageError("sweep needs at least one --grid NODE.PARAM=V1,V2");
  set_up_logging(args);
  const fs::path out = args.last("out");
  check_output_folder(out);
  const std::string graph_file = args.positional[0];
  std::vector<GridAxis> axes;
  std::vector<uint64_t> seeds;
  try {
    for (const auto& g : args.all("grid")) axes.push_back(parse_grid(g));
    if (args.has("seeds")) seeds = parse_seeds(args.last("seeds"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  parse_threads(args);  // a bad --threads is one usage error, before the first run
  // Every combination is validated up front: a misspelt grid param is one error, not N failed
  // runs.
  // "{seed}" in --input, --set and --grid values is the run's seed: --input
  // 'embedded:or?seed={seed}' gives every seed a capture of its own.
  const auto with_seed = [](std::string v, uint64_t seed) {
    for (size_t at; (at = v.find("{seed}")) != std::string::npos;)
      v.replace(at, 6, std::to_string(seed));
    return v;
  };
  const auto combination_options = [&](const SweepPoint& p) {
    LoadOptions lopt = load_options(args);
    for (const auto& [param, value] : p.params) lopt.sets.push_back(param + "=" + value);
    for (auto& set : lopt.sets) set = with_seed(set, p.seed);
    if (args.has("input")) lopt.vars["input"] = with_seed(args.last("input"), p.seed);
    return lopt;
  };
  if (seeds.empty()) {
    const auto graph = load_checked(graph_file, registry, load_options(args));
    if (!graph) return exit_code::kInvalidGraph;
    seeds = {run_seed(*graph)};
  }
  std::vector<SweepPoint> points;
  try {
    points = sweep_points(axes, seeds);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  for (const auto& p : points)
    if (p.seed == seeds.front() && !load_checked(graph_file, registry, combination_options(p)))
      return exit_code::kInvalidGraph;

  install_interrupt_handlers();
  std::vector<SweepRun> runs;
  std::vector<std::string> headline;
  nlohmann::json table;
  spdlog::info("sweep: {} runs of {} -> {}", points.size(), graph_file, out.string());
  for (size_t i = 0; i < points.size() && !interrupt_flag().load(); ++i) {
    // Room for any size_t: g++ warned that 16 bytes could truncate "%04zu" past 10^15 runs.
    char name[24];
    std::snprintf(name, sizeof name, "%04zu", i);
    SweepRun run;
    run.dir = (fs::path("runs") / name).generic_string();
    run.point = points[i];
    const fs::path dir = out / run.dir;
    std::vector<std::string> child = child_run_command(args, graph_file, dir, "warn");
    child.insert(child.end(), {"--seed", std::to_string(run.point.seed)});
    if (args.has("input"))
      child.insert(child.end(), {"--input", with_seed(args.last("input"), run.point.seed)});
    for (const auto& s : combination_options(run.point).sets)
      child.insert(child.end(), {"--set", s});
    std::string label;
    for (const auto& [param, value] : run.point.params) label += param + "=" + value + " ";
    spdlog::info("sweep {}/{}: {}seed {}", i + 1, points.size(), label, run.point.seed);
    fs::create_directories(dir);
    const ChildRun r = run_child_process(child, (dir / "gslift.log").string(), &interrupt_flag());
    try {
      const nlohmann::json record = parse_json(read_input_file(dir / "run.json", "run.json"));
      run = sweep_run_from_record(record, run);
      if (headline.empty() && run.status == "ok") headline = headline_metrics(record);
    } catch (const std::exception& e) {
      // The child died before writing its record (a crash, or a kill): the row says how.
      // Its own peak memory is unknown: wait4's includes this process's (child_process.hpp).
      run.status = "failed";
      run.total_s = r.wall_s;
      run.peak_rss_mb = 0;
      run.error =
          "gslift run " + child_exit_text(r) +
          (WIFSIGNALED(r.status) ? std::string()
                                 : " without a readable run.json (" + std::string(e.what()) + ")");
    }
    if (run.status != "ok") spdlog::warn("sweep {}: {}: {}", run.dir, run.status, run.error);
    runs.push_back(run);
    table = sweep_json(graph_file, axes, seeds, runs);
    table["headline"] = headline;
    write_file_atomically(out / "sweep.json", json_text(table));
    write_file_atomically(out / "results.csv", sweep_runs_csv(axes, runs));
    write_file_atomically(out / "summary.csv", sweep_summary_csv(axes, table));
  }
  std::printf("%s", sweep_table(axes, table, headline).c_str());
  std::printf("sweep: %zu of %zu runs\nresults: %s\n", runs.size(), points.size(),
              results_line(out).c_str());
  if (interrupt_flag().load()) return exit_code::kInterrupted;
  for (const auto& r : runs)
    if (r.status != "ok") return exit_code::kBatchPartial;
  return exit_code::kOk;
}

int cmd_report(int argc, char** argv, const Registry&) {
  const Args args = parse_args(argc, argv, 2, {"max-picture-mb"}, {"help"});
  if (args.flags.count("help")) return print_command_help(command_named("report")), 0;
  if (args.positional.size() != 1) throw UsageError("report expects one run or sweep folder");
  report::ReportOptions opt;
  if (args.has("max-picture-mb"))
    opt.max_picture_bytes =
        uintmax_t(parse_integer("max-picture-mb", args.last("max-picture-mb"), 0, 1 << 20)) << 20;
  report::ReportStats stats;
  const fs::path page = report::write_report(args.positional[0], opt, &stats);
  if (report::is_sweep_dir(args.positional[0]))
    std::printf("report: %s (and %zu run reports, their %zu pictures linked)\n",
                page.string().c_str(), stats.runs, stats.pictures_linked);
  else
    std::printf("report: %s (%zu pictures embedded, %zu skipped)\n", page.string().c_str(),
                stats.pictures_embedded, stats.pictures_skipped);
  return exit_code::kOk;
}

int cmd_diff(int argc, char** argv, const Registry&) {
  const Args args = parse_args(argc, argv, 2, {}, {"help"});
  if (args.flags.count("help")) return print_command_help(command_named("diff")), 0;
  if (args.positional.size() != 2) throw UsageError("diff expects two run folders");
  const report::RunRecord a = report::read_run_record(args.positional[0]);
  const report::RunRecord b = report::read_run_record(args.positional[1]);
  const report::RunDiff diff = report::diff_runs(a, b);
  std::printf("%s", terminal_safe(report::diff_text(diff, a, b)).c_str());
  return diff.differs() ? exit_code::kRunsDiffer : exit_code::kOk;
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
    std::fprintf(stderr, "gslift: %s\nsee 'gslift --help'\n", terminal_safe(e.what()).c_str());
    return exit_code::kUsage;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kBadInput;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kCannotWrite;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kInternal;
  }
}

}  // namespace gslift
