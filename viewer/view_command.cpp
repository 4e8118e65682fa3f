#include "viewer/view_command.hpp"

#include <pthread.h>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include "base/errors.hpp"
#include "runtime/exit_codes.hpp"
#include "viewer/view_server.hpp"

namespace gslift {
namespace {

const char* const kHelp =
    "usage: gslift view RUN_FOLDER [--host H] [--port P]\n"
    "       gslift view MODEL.ply --input CAPTURE [--poses FILE] [--host H] [--port P]\n\n"
    "Serves a web page of the scene on http://H:P/ and prints that URL: frames rendered by\n"
    "gslift's rasterizer from every capture camera, orbit / pan / zoom, instances with a legend,\n"
    "a click or a scribble as a SAGA prompt on the model's per-Gaussian features, a LangOR text\n"
    "query, the selection exported as a PLY and the view as a PNG (docs/viewer.md). Every asset "
    "is\n"
    "served by gslift; no file is read on request. SIGINT / SIGTERM stop it.\n\n"
    "options:\n"
    "  --input CAPTURE   the capture of MODEL.ply (a folder or embedded:or?seed=N)\n"
    "  --poses FILE      the poses MODEL.ply was trained at (a run's recon/refined_poses.txt;\n"
    "                    a run folder's are found without it)\n"
    "  --host H          the address to listen on (default 127.0.0.1: this machine only)\n"
    "  --port P          the port (default 8765; 0: any free port)\n";

}  // namespace

int view_main(int argc, char** argv) {
  std::string target, input, poses, host = "127.0.0.1";
  int port = 8765;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kHelp;
      return exit_code::kOk;
    }
    if (arg == "--input" || arg == "--poses" || arg == "--host" || arg == "--port") {
      if (i + 1 >= argc) {
        std::cerr << "gslift view: " << arg << " needs a value (see gslift view --help)\n";
        return exit_code::kUsage;
      }
      const std::string value = argv[++i];
      if (arg == "--input") input = value;
      if (arg == "--poses") poses = value;
      if (arg == "--host") host = value;
      if (arg == "--port") {
        char* end = nullptr;
        const long p = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || p < 0 || p > 65535) {
          std::cerr << "gslift view: --port takes a number from 0 to 65535, not '" << value
                    << "'\n";
          return exit_code::kUsage;
        }
        port = static_cast<int>(p);
      }
      continue;
    }
    if (arg.rfind("--", 0) == 0 || !target.empty()) {
      std::cerr << "gslift view: unexpected argument '" << arg << "' (see gslift view --help)\n";
      return exit_code::kUsage;
    }
    target = arg;
  }
  const bool is_ply = target.size() > 4 && target.compare(target.size() - 4, 4, ".ply") == 0;
  if (target.empty() || (is_ply && input.empty()) ||
      (!is_ply && !(input.empty() && poses.empty()))) {
    std::cerr << "gslift view: give a run folder, or a MODEL.ply with --input CAPTURE [--poses "
                 "FILE] (see gslift view --help)\n";
    return exit_code::kUsage;
  }
  // SIGINT and SIGTERM are taken by one thread that stops the server: blocked here, before any
  // thread starts, so that every thread inherits the mask.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  try {
    ViewSession session(is_ply ? open_model(target, input, poses) : open_run_folder(target));
    if (!session.scene().poses_file.empty())
      std::cerr << "gslift view: the capture's poses replaced by " << session.scene().poses_file
                << " (the poses the model was trained at)\n";
    ViewServer server(session);
    const int bound = server.bind(host, port);
    if (host != "127.0.0.1" && host != "localhost" && host != "::1")
      std::cerr << "gslift view: listening on " << host
                << ": every machine that reaches it can read the scene\n";
    std::cout << "gslift view: " << session.scene().title << " at http://"
              << (host.find(':') != std::string::npos ? "[" + host + "]" : host) << ":" << bound
              << "/ (Ctrl-C stops)" << std::endl;
    std::atomic<bool> stopped{false};
    std::thread stopper([&] {
      int signal = 0;
      sigwait(&stop_signals, &signal);
      stopped = true;
      server.stop();
    });
    server.serve();
    // serve() also ends when the listening socket fails: wake the stopper then.
    if (!stopped) pthread_kill(stopper.native_handle(), SIGTERM);
    stopper.join();
  } catch (const InputError& e) {
    std::cerr << "gslift view: " << e.what() << "\n";
    return exit_code::kBadInput;
  }
  return exit_code::kOk;
}

}  // namespace gslift
