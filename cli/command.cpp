#include "cli/command.hpp"

#include <cstdio>
#include <stdexcept>

namespace gslift {

const char* const kExitCodes =
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

void CommandTable::add(Command command) {
  if (find(command.name)) throw std::logic_error("command '" + command.name + "' added twice");
  commands_.push_back(std::move(command));
}

const Command* CommandTable::find(const std::string& name) const {
  for (const auto& c : commands_)
    if (c.name == name) return &c;
  return nullptr;
}

void print_command_help(const CommandHelp& help) {
  const std::string text = help.usage + "options:\n" + options_help(help.options) + help.epilogue;
  std::printf("%s\n%s", text.c_str(), kExitCodes);
}

}  // namespace gslift
