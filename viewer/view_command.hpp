// `gslift view RUN_FOLDER` / `gslift view MODEL.ply --input CAPTURE`: loads the scene, serves the
// viewer page on 127.0.0.1 (--host, --port to change) and prints its URL; SIGINT or SIGTERM stop
// it (exit 0).
#pragma once

namespace gslift {

// argv[0] is "view". Returns a process exit code (runtime/exit_codes.hpp).
int view_main(int argc, char** argv);

}  // namespace gslift
