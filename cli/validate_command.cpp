// `gslift validate GRAPH`: load and validate without running; every diagnostic printed, or the
// resolved graph with --print.
#include <cstdio>
#include <string>

#include "cli/graph_file.hpp"
#include "cli/graph_yaml.hpp"
#include "cli/runtime_commands.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/preflight.hpp"

namespace gslift {

namespace {

const CommandHelp& validate_help() {
  static const CommandHelp help{
      "usage: gslift validate GRAPH [--set NODE.PARAM=VALUE]... [--input PATH] [--seed S]\n"
      "                             [--print]\n\n"
      "Prints every diagnostic (file:line:col) and exits 3 when the graph is invalid.\n\n",
      {kSetOption,
       kInputOption.described(
           "graph var ${input}; the capture is checked for what each node needs"),
       kSeedOption.described("graph var ${seed}"),
       {"print", "", "print the resolved graph (defaults filled in) as YAML"},
       kLogLevelOption,
       kHelpOption},
      ""};
  return help;
}

int cmd_validate(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, validate_help().options);
  if (args.flags.count("help")) return print_command_help(validate_help()), 0;
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

}  // namespace

Command validate_command() {
  return {"validate", "check a graph without running it", cmd_validate};
}

}  // namespace gslift
