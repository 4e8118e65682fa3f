#include "nodes/synth/synth_command.hpp"

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "nodes/synth/or_capture.hpp"
#include "nodes/synth/or_rig_capture.hpp"
#include "runtime/exit_codes.hpp"

namespace gslift {

namespace {

void print_help(std::ostream& out) {
  out << "usage: gslift synth --out DIR [--seed S] [--phase P] [--views N] [--width W --height H]\n"
         "                    [--preset P] [--set knob=value]... [--layout rig [--time-steps "
         "T]\n"
         "                    [--rig-depth D]]\n\n"
         "Generates an embedded operating-room capture (images, depth prior, ground truth,\n"
         "COLMAP model, simulated VLM replies and SAM masks) in gslift's capture layout.\n"
         "The same settings give byte-identical files.\n\n"
         "  --out DIR      folder to create (must not exist, or be empty)\n"
         "  --layout L     gslift (default) | rig: a multi-camera RGB-D rig recording in\n"
         "                 4D-OR's layout, one folder per time step (docs/or-rig.md)\n"
         "  --time-steps T rig: time steps, 1..1000 (default 1; the scene is static)\n"
         "  --rig-depth D  rig: sensor (default; depth from a depth camera of its own) |\n"
         "                 registered (MM-OR: depth in the colour camera's grid, half size)\n"
         "  --seed S       layout seed (default 0)\n"
         "  --phase P      preparation | surgery | closing (default surgery)\n"
         "  --views N      cameras, 4..8 (default 5; one in five is held out)\n"
         "  --width W      image width (default 640)\n"
         "  --height H     image height (default 480)\n"
         "  --preset P     easy | default | hard: failure rates of the simulated models\n"
         "  --set k=v      override one knob (applied after the preset); knobs:\n";
  const synth::SynthKnobs defaults;
  for (const synth::KnobField& k : synth::synth_knob_table().fields()) {
    out << "      " << k.spec.name << " (default " << synth::knob_value(defaults, k)
        << "): " << k.spec.doc << "\n";
  }
}

}  // namespace

int synth_main(int argc, char** argv) {
  std::vector<std::pair<std::string, std::string>> entries;
  std::string out_dir, layout = "gslift";
  int time_steps = 1;
  bool time_steps_given = false;
  std::string rig_depth;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      print_help(std::cout);
      return exit_code::kOk;
    }
    if (i + 1 >= argc) {
      std::cerr << "gslift synth: " << arg << " needs a value (see gslift synth --help)\n";
      return exit_code::kUsage;
    }
    const std::string value = argv[++i];
    if (arg == "--out") {
      out_dir = value;
    } else if (arg == "--layout") {
      if (value != "gslift" && value != "rig") {
        std::cerr << "gslift synth: --layout is gslift or rig, got '" << value << "'\n";
        return exit_code::kUsage;
      }
      layout = value;
    } else if (arg == "--time-steps") {
      char* end = nullptr;
      const long t = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != 0 || t < 1 || t > 1000) {
        std::cerr << "gslift synth: --time-steps is 1..1000, got '" << value << "'\n";
        return exit_code::kUsage;
      }
      time_steps = static_cast<int>(t);
      time_steps_given = true;
    } else if (arg == "--rig-depth") {
      if (value != "sensor" && value != "registered") {
        std::cerr << "gslift synth: --rig-depth is sensor or registered, got '" << value << "'\n";
        return exit_code::kUsage;
      }
      rig_depth = value;
    } else if (arg == "--set") {
      const auto eq = value.find('=');
      if (eq == std::string::npos || eq == 0) {
        std::cerr << "gslift synth: --set expects knob=value, got '" << value << "'\n";
        return exit_code::kUsage;
      }
      entries.emplace_back(value.substr(0, eq), value.substr(eq + 1));
    } else if (arg == "--seed" || arg == "--phase" || arg == "--views" || arg == "--width" ||
               arg == "--height" || arg == "--preset") {
      entries.emplace_back(arg.substr(2), value);
    } else {
      std::cerr << "gslift synth: unknown option " << arg << " (see gslift synth --help)\n";
      return exit_code::kUsage;
    }
  }
  if (out_dir.empty()) {
    std::cerr << "gslift synth: --out DIR is required (see gslift synth --help)\n";
    return exit_code::kUsage;
  }
  if ((time_steps_given || !rig_depth.empty()) && layout != "rig") {
    std::cerr << "gslift synth: " << (time_steps_given ? "--time-steps" : "--rig-depth")
              << " needs --layout rig\n";
    return exit_code::kUsage;
  }
  synth::OrCaptureSettings settings;
  try {
    settings = synth::make_settings(entries);
  } catch (const std::invalid_argument& e) {
    std::cerr << "gslift synth: " << e.what() << "\n";
    return exit_code::kUsage;
  }
  try {
    const auto start = std::chrono::steady_clock::now();
    if (layout == "rig")
      synth::write_or_rig_recording(
          settings, out_dir, time_steps,
          rig_depth == "registered" ? synth::RigDepth::registered : synth::RigDepth::sensor);
    else
      synth::write_or_capture(settings, out_dir);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "wrote " << synth::capture_name(settings) << " (" << settings.scene.views
              << " views, " << settings.scene.width << "x" << settings.scene.height << ", preset "
              << enum_name(settings.preset, synth::preset_names()) << ")"
              << (layout == "rig"
                      ? " as a rig recording of " + std::to_string(time_steps) + " time step(s)"
                      : std::string())
              << " to " << out_dir << " in " << seconds << " s\n";
    return exit_code::kOk;
  } catch (const std::invalid_argument& e) {
    std::cerr << "gslift synth: " << e.what() << "\n";
    return exit_code::kUsage;
  } catch (const std::exception& e) {
    std::cerr << "gslift synth: cannot write " << out_dir << ": " << e.what() << "\n";
    return exit_code::kBadInput;
  }
}

}  // namespace gslift
