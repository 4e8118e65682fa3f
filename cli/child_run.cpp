#include "cli/child_run.hpp"

namespace gslift {

namespace fs = std::filesystem;

std::vector<std::string> child_run_command(const Args& args, const std::string& graph_file,
                                           const fs::path& out, const std::string& log_level) {
  std::vector<std::string> child = {fs::read_symlink("/proc/self/exe").string(),
                                    "run",
                                    graph_file,
                                    "--out",
                                    out.string(),
                                    "--threads",
                                    std::to_string(parse_threads(args)),
                                    "--log-level",
                                    log_level};
  for (const char* opt : {"cache-dir", "cache-size"})
    if (args.has(opt)) child.insert(child.end(), {std::string("--") + opt, args.last(opt)});
  if (args.flags.count("no-cache")) child.push_back("--no-cache");
  return child;
}

}  // namespace gslift
