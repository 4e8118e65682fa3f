#include "cli/cli.hpp"
#include "cli/program_command.hpp"
#include "cli/runtime_commands.hpp"
#include "nodes/builtin.hpp"
#include "nodes/inference/segment_session.hpp"
#include "nodes/synth/synth_command.hpp"
#include "runtime/allocator.hpp"
#include "viewer/view_command.hpp"

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  gslift::Registry registry;
  gslift::register_builtin_nodes(registry);
  gslift::CommandTable commands;
  gslift::add_runtime_commands(commands);
  commands.add(gslift::program_command(
      "synth", "write an embedded operating-room capture to a folder", gslift::synth_main));
  commands.add(gslift::program_command(
      "segment", "answer SAGA prompts (JSON lines on stdin) on a feature model",
      gslift::segment_main));
  commands.add(gslift::program_command(
      "view", "serve a run (or a PLY) as a local web page: orbit, click, query, export",
      gslift::view_main));
  return gslift::cli_main(argc, argv, registry, commands);
}
