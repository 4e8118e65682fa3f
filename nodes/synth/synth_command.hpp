// `gslift synth`: writes an embedded OR capture to a folder. app/main.cpp adds it to the command
// table (cli/program_command.hpp).
#pragma once

namespace gslift {

// argv[0] is "synth"; the rest are the command's options (see --help). Returns a process exit
// code from runtime/exit_codes.hpp.
int synth_main(int argc, char** argv);

}  // namespace gslift
