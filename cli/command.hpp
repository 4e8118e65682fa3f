// One command of the gslift command line, and the table every command registers into: the
// runtime's own (cli/runtime_commands.hpp) and the programs main() brings from the node families
// (`gslift synth`, `gslift segment`: cli/program_command.hpp). cli_main dispatches through it and
// `gslift --help` lists it in its order.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cli/options.hpp"
#include "runtime/registry.hpp"

namespace gslift {

struct Command {
  std::string name;
  std::string summary;  // its line in `gslift --help`
  // argv[1] is the command's name, its arguments follow; returns the process exit code.
  std::function<int(int argc, char** argv, const Registry& registry)> run;
};

class CommandTable {
 public:
  // Throws std::logic_error when the name is taken.
  void add(Command command);
  const Command* find(const std::string& name) const;
  const std::vector<Command>& commands() const { return commands_; }

 private:
  std::vector<Command> commands_;
};

// What `gslift COMMAND --help` prints: the usage and what the command does, its options (the
// lines come from their declarations), then anything the command adds after them.
struct CommandHelp {
  std::string usage;  // ends with the blank line before "options:"
  OptionList options;
  std::string epilogue;  // after the options, from its blank line on
};

// The help, then the exit codes.
void print_command_help(const CommandHelp& help);

// The exit codes every command shares (runtime/exit_codes.hpp), as `--help` lists them.
extern const char* const kExitCodes;

}  // namespace gslift
