#include "nodes/builtin.hpp"
#include "nodes/inference/segment_session.hpp"
#include "nodes/synth/synth_command.hpp"
#include "runtime/allocator.hpp"
#include "cli/cli.hpp"

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  gslift::Registry registry;
  gslift::register_builtin_nodes(registry);
  const std::vector<gslift::ExtraCommand> extra = {
      {"synth", "write an embedded operating-room capture to a folder", gslift::synth_main},
      {"segment", "answer SAGA prompts (JSON lines on stdin) on a feature model",
       gslift::segment_main}};
  return gslift::cli_main(argc, argv, registry, extra);
}
