// The command line's options: each declared once with its help line (Option), parsed from argv by
// the list a command takes (parse_args), and the groups several commands share together with the
// code that reads them: graph vars and --set, --threads, --log-level, the stage cache.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/loader.hpp"
#include "runtime/executor.hpp"
#include "runtime/stage_cache.hpp"

namespace gslift {

// A command-line mistake: printed with a pointer to --help, exit code kUsage.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Option {
  std::string name;   // without the dashes; "help" also answers to -h
  std::string value;  // what its value is called in the help ("N", "DIR"); empty for a flag
  std::string doc;    // the help text; '\n' starts a continuation line

  // The same option as one command describes it ("worker threads per capture, ...").
  Option described(std::string command_doc) const {
    Option o = *this;
    o.doc = std::move(command_doc);
    return o;
  }
};
using OptionList = std::vector<Option>;

// The options every command shares, and the groups several do.
extern const Option kHelpOption;      // -h, --help
extern const Option kSetOption;       // --set NODE.PARAM=VALUE, repeatable
extern const Option kInputOption;     // --input PATH: graph var ${input}
extern const Option kSeedOption;      // --seed S: graph var ${seed}
extern const Option kOutOption;       // --out DIR
extern const Option kThreadsOption;   // --threads N
extern const Option kLogLevelOption;  // --log-level L
// --cache-dir, --cache-size, --no-cache: the stage cache of run, batch and sweep.
extern const OptionList kCacheOptions;

// "  --name VALUE            doc" a line per option (and per continuation line of its doc).
std::string options_help(const OptionList& options);

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

// argv[first..] against `options`: an option not among them is a UsageError that names the
// nearest one, as is a flag given a value or an option missing its value.
Args parse_args(int argc, char** argv, int first, const OptionList& options);

// `text` as an integer in [min, max], else a UsageError naming --option.
int64_t parse_integer(const std::string& option, const std::string& text, int64_t min,
                      int64_t max = std::numeric_limits<int64_t>::max());

// --threads (0 = all cores).
int64_t parse_threads(const Args& args);
// --log-level: the level of gslift's logger, which writes to stderr.
void set_up_logging(const Args& args);
// --input and --seed become graph vars ${input} and ${seed}; --set is passed through.
LoadOptions load_options(const Args& args);
// The run options known from the command line alone, checked before the graph is loaded; the
// seed comes from the loaded graph (run_seed).
RunOptions command_line_run_options(const Args& args);
// The stage cache (runtime/stage_cache.hpp): on unless --no-cache, in --cache-dir (default: the
// user's cache folder), capped at --cache-size GB (0 = no cap). A default folder that cannot be
// made only costs the cache (a warning); one the user named is bad input.
std::unique_ptr<StageCache> command_line_cache(const Args& args);

}  // namespace gslift
