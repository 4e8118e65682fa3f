// `gslift diff RUN_A RUN_B`: what differs between two runs' run.json (report/run_diff.hpp).
#include <cstdio>

#include "base/utf8.hpp"
#include "cli/runtime_commands.hpp"
#include "report/run_diff.hpp"
#include "runtime/exit_codes.hpp"

namespace gslift {

namespace {

const CommandHelp& diff_help() {
  static const CommandHelp help{
      "usage: gslift diff RUN_A RUN_B\n\n"
      "Reads both run.json files and prints what differs: status, graph structure (nodes added,\n"
      "removed, retyped, rewired; graph params), params per node and records per node (numbers\n"
      "with both values, the delta and the relative change). Time, memory and cache state are\n"
      "printed apart and do not count. Exits 0 when nothing counted differs, 1 when something\n"
      "does (like diff(1)), 4 when a folder is not a readable run.\n\n",
      {kHelpOption},
      ""};
  return help;
}

int cmd_diff(int argc, char** argv, const Registry&) {
  const Args args = parse_args(argc, argv, 2, diff_help().options);
  if (args.flags.count("help")) return print_command_help(diff_help()), 0;
  if (args.positional.size() != 2) throw UsageError("diff expects two run folders");
  const report::RunRecord a = report::read_run_record(args.positional[0]);
  const report::RunRecord b = report::read_run_record(args.positional[1]);
  const report::RunDiff diff = report::diff_runs(a, b);
  std::printf("%s", terminal_safe(report::diff_text(diff, a, b)).c_str());
  return diff.differs() ? exit_code::kRunsDiffer : exit_code::kOk;
}

}  // namespace

Command diff_command() {
  return {"diff", "print the params, records and graph changes between two runs", cmd_diff};
}

}  // namespace gslift
