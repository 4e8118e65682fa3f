// `gslift nodes [TYPE]`: the node catalogue, or one type's ports and params.
#include <cstdio>
#include <string>

#include "cli/node_catalogue.hpp"
#include "cli/runtime_commands.hpp"
#include "graph/suggest.hpp"
#include "runtime/exit_codes.hpp"

namespace gslift {

namespace {

const CommandHelp& nodes_help() {
  static const CommandHelp help{
      "usage: gslift nodes [TYPE]\n\n"
      "Without TYPE: every registered node type with its one-line doc. With TYPE: its input\n"
      "and output ports (type, doc) and params (type, default, range, choices, doc).\n\n",
      {kHelpOption},
      ""};
  return help;
}

int cmd_nodes(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, nodes_help().options);
  if (args.flags.count("help")) return print_command_help(nodes_help()), 0;
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

}  // namespace

Command nodes_command() {
  return {"nodes", "list node types, or document one", cmd_nodes};
}

}  // namespace gslift
