// The runtime's commands, one file each in cli/ (<name>_command.cpp).
#pragma once

#include "cli/command.hpp"

namespace gslift {

Command run_command();       // run a graph on one capture
Command validate_command();  // check a graph without running it
Command nodes_command();     // the node catalogue
Command batch_command();     // a graph over many captures
Command sweep_command();     // a graph over a grid of params and seeds
Command report_command();    // report.html for a run or sweep folder
Command diff_command();      // what differs between two runs

// All of them, in the order `gslift --help` lists them.
void add_runtime_commands(CommandTable& table);

}  // namespace gslift
