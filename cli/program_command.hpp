// A command that is a program of its own, brought in by main() from a node family (`gslift synth`
// from nodes/synth, `gslift segment` from nodes/inference): it gets argv[0] = its name and parses
// its own options, so that the families stay free of the command line's code.
#pragma once

#include <functional>
#include <string>

#include "cli/command.hpp"

namespace gslift {

// The program as a command of the table. It takes --threads and --log-level like run and batch:
// they are taken out of its arguments and applied around it (--threads caps every TBB loop, as in
// execute()); its --help is followed by their lines.
Command program_command(std::string name, std::string summary,
                        std::function<int(int argc, char** argv)> program);

}  // namespace gslift
