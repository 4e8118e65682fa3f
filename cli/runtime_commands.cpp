#include "cli/runtime_commands.hpp"

namespace gslift {

void add_runtime_commands(CommandTable& table) {
  for (Command c : {run_command(), validate_command(), nodes_command(), batch_command(),
                    sweep_command(), report_command(), diff_command()})
    table.add(std::move(c));
}

}  // namespace gslift
