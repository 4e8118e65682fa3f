#include "cli/program_command.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <vector>

#include <oneapi/tbb/global_control.h>

namespace gslift {

namespace {

int run_program(const std::function<int(int, char**)>& program, int argc, char** argv) {
  static const OptionList common = {kThreadsOption, kLogLevelOption};
  std::vector<char*> own = {argv[1]};
  std::vector<char*> taken = {argv[0], argv[1]};
  bool help = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    help |= a == "--help" || a == "-h";
    const bool is_common =
        a.rfind("--", 0) == 0 && std::any_of(common.begin(), common.end(), [&](const Option& o) {
          return o.name == a.substr(2, a.find('=') - 2);
        });
    if (!is_common) {
      own.push_back(argv[i]);
      continue;
    }
    taken.push_back(argv[i]);
    if (a.find('=') == std::string::npos && i + 1 < argc) taken.push_back(argv[++i]);
  }
  const Args args = parse_args(int(taken.size()), taken.data(), 2, common);
  set_up_logging(args);
  const auto threads = static_cast<size_t>(parse_threads(args));
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
  const int code = program(int(own.size()), own.data());
  if (help)
    std::printf("\noptions gslift takes for this command too:\n%s", options_help(common).c_str());
  return code;
}

}  // namespace

Command program_command(std::string name, std::string summary,
                        std::function<int(int argc, char** argv)> program) {
  return {std::move(name), std::move(summary),
          [program = std::move(program)](int argc, char** argv, const Registry&) {
            return run_program(program, argc, argv);
          }};
}

}  // namespace gslift
