// The gslift command line: a visible table of commands, each parsing its own options, then
// load -> validate -> run -> write, with one place that maps failures to exit codes
// (runtime/exit_codes.hpp).
#include "cli/cli.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "base/utf8.hpp"
#include "cli/options.hpp"
#include "graph/suggest.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/version.hpp"

namespace gslift {

namespace {

void print_global_help(const CommandTable& commands) {
  std::printf(
      "gslift %s: posed views of a room -> 3D Gaussian Splatting scene, segmented and "
      "queryable.\n\n"
      "usage: gslift COMMAND [options]    (gslift COMMAND --help for its options)\n\n"
      "commands:\n",
      gslift_version());
  for (const auto& c : commands.commands())
    std::printf("  %-10s %s\n", c.name.c_str(), c.summary.c_str());
  std::printf(
      "\nglobal options:\n  -h, --help     this help\n  --version      print the version\n\n%s",
      kExitCodes);
}

int dispatch(int argc, char** argv, const Registry& registry, const CommandTable& commands) {
  if (argc < 2) {
    print_global_help(commands);
    return exit_code::kUsage;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || first == "help") {
    print_global_help(commands);
    return exit_code::kOk;
  }
  if (first == "--version") {
    std::printf("gslift %s (%s)\n", gslift_version(), gslift_git_version());
    return exit_code::kOk;
  }
  if (const Command* c = commands.find(first)) return c->run(argc, argv, registry);
  std::vector<std::string> names;
  for (const auto& c : commands.commands()) names.push_back(c.name);
  const std::string hint = suggest(first, names, true);
  throw UsageError("unknown command '" + first + "' (" + hint + ")");
}

}  // namespace

int cli_main(int argc, char** argv, const Registry& registry, const CommandTable& commands) {
  try {
    return dispatch(argc, argv, registry, commands);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "gslift: %s\nsee 'gslift --help'\n", terminal_safe(e.what()).c_str());
    return exit_code::kUsage;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kBadInput;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kCannotWrite;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", terminal_safe(e.what()).c_str());
    return exit_code::kInternal;
  }
}

}  // namespace gslift
