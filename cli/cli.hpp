#pragma once

#include <functional>
#include <string>
#include <vector>

#include "runtime/registry.hpp"

namespace gslift {

// A command that lives outside the runtime (e.g. `gslift synth`, which belongs to nodes/synth):
// main() hands it in, so the runtime stays free of domain code. `run` gets argv[0] = its name.
struct ExtraCommand {
  std::string name;
  std::string summary;
  std::function<int(int argc, char** argv)> run;
};

// The gslift command line (docs/cli.md). Returns the process exit code.
int cli_main(int argc, char** argv, const Registry& registry,
             const std::vector<ExtraCommand>& extra = {});

}  // namespace gslift
