// `gslift report DIR`: report.html for a run or sweep folder (report/report_page.hpp).
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "cli/runtime_commands.hpp"
#include "report/report_page.hpp"
#include "runtime/exit_codes.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

const CommandHelp& report_help() {
  static const CommandHelp help{
      "usage: gslift report DIR [--max-picture-mb N]\n\n"
      "Writes DIR/report.html, one self-contained page (pictures embedded, charts as SVG, no\n"
      "external links). For a run folder (run.json): the results first (headline metrics\n"
      "against the README's floors, the per-class table, ground truth | render | instances\n"
      "per held-out view), then the graph, a timeline of the nodes, each node's time, memory\n"
      "and records, and every other picture the run wrote. For a sweep folder (sweep.json):\n"
      "the summary table, each metric against time (runs from the stage cache marked cached),\n"
      "memory and every varied param, and a section per run; each run's own report.html is\n"
      "written too, with its pictures linked (gslift report RUN_DIR embeds them).\n\n",
      {{"max-picture-mb", "N",
        "embed pictures until their files add up to N MB; the rest are\n"
        "listed with links (default 32)"},
       kHelpOption},
      ""};
  return help;
}

int cmd_report(int argc, char** argv, const Registry&) {
  const Args args = parse_args(argc, argv, 2, report_help().options);
  if (args.flags.count("help")) return print_command_help(report_help()), 0;
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

}  // namespace

Command report_command() {
  return {"report", "write report.html for a run or sweep folder", cmd_report};
}

}  // namespace gslift
