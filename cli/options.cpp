#include "cli/options.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "base/errors.hpp"
#include "graph/suggest.hpp"
#include "runtime/log_format.hpp"
#include "runtime/signals.hpp"

namespace gslift {

namespace fs = std::filesystem;

const Option kHelpOption{"help", "", "this help"};
const Option kSetOption{"set", "NODE.PARAM=VALUE",
                        "override a param (repeatable); NODE.type=TYPE swaps a stage,\n"
                        "NAME=VALUE sets the graph param NAME"};
const Option kInputOption{"input", "PATH", "the capture to process (graph var ${input})"};
const Option kSeedOption{"seed", "S",
                         "run seed (graph var ${seed}; default: the graph's seed or 0)"};
const Option kOutOption{"out", "DIR", "results folder"};
const Option kThreadsOption{"threads", "N",
                            "worker threads, 0 = all cores (default 0, at most 1024)"};
const Option kLogLevelOption{"log-level", "L",
                             "trace, debug, info, warn, error, critical, off (default info)"};
const OptionList kCacheOptions = {{"cache-dir", "DIR",
                                   "stage cache folder (default $GSLIFT_STAGE_CACHE, else\n"
                                   "~/.cache/gslift/stages; $GSLIFT_CACHE or $XDG_CACHE_HOME\n"
                                   "move ~/.cache/gslift)"},
                                  {"cache-size", "GB",
                                   "cap of the cache folder, least recently used entries go first\n"
                                   "(default 10, 0 = no cap)"},
                                  {"no-cache", "", "run every node; read and write no cache"}};

std::string options_help(const OptionList& options) {
  // The docs start in column 27; a name as long as that pushes its doc one space on.
  constexpr size_t kNameWidth = 24;
  std::string text;
  for (const Option& o : options) {
    const std::string name =
        o.name == "help" ? "-h, --help" : "--" + o.name + (o.value.empty() ? "" : " " + o.value);
    text += "  " + name + std::string(name.size() < kNameWidth ? kNameWidth - name.size() : 1, ' ');
    size_t start = 0;
    for (size_t end; (end = o.doc.find('\n', start)) != std::string::npos; start = end + 1)
      text += o.doc.substr(start, end - start) + "\n" + std::string(kNameWidth + 2, ' ');
    text += o.doc.substr(start) + "\n";
  }
  return text;
}

Args parse_args(int argc, char** argv, int first, const OptionList& options) {
  std::vector<std::string> valued, flag_names;
  for (const Option& o : options) (o.value.empty() ? flag_names : valued).push_back(o.name);
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
                      int64_t max) {
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

int64_t parse_threads(const Args& args) {
  return parse_integer("threads", args.last("threads", "0"), 0, kMaxThreads);
}

void set_up_logging(const Args& args) {
  if (!spdlog::get("gslift")) spdlog::set_default_logger(spdlog::stderr_color_mt("gslift"));
  spdlog::set_formatter(log_formatter());
  const std::string level = args.last("log-level", "info");
  static const std::vector<std::string> levels = {"trace", "debug",    "info", "warn",
                                                  "error", "critical", "off"};
  if (std::find(levels.begin(), levels.end(), level) == levels.end()) {
    const std::string hint = suggest(level, levels, true);
    throw UsageError("unknown --log-level '" + level + "' (" + hint + ")");
  }
  spdlog::set_level(spdlog::level::from_str(level));
}

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

RunOptions command_line_run_options(const Args& args) {
  RunOptions opt;
  opt.threads = static_cast<int>(parse_threads(args));
  opt.run_input = args.last("input");
  opt.cancel = &interrupt_flag();
  return opt;
}

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

}  // namespace gslift
