// The embedded operating room: a seeded layout of OR entities built from primitives, the lights,
// and the ceiling-corner cameras, as in the public OR datasets (4D-OR, MM-OR). Every entity is one
// instance with one semantic class; the room itself is background (instance 0, class 0).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/camera.hpp"
#include "nodes/synth/primitive.hpp"
#include "param/param_table.hpp"

namespace gslift::synth {

// Semantic classes 1..12; the names are what a user would type as a query.
enum OrClass : int {
  kOperatingTable = 1,
  kPatient,
  kHeadSurgeon,
  kAssistantSurgeon,
  kCirculatingNurse,
  kAnaesthetist,
  kAnesthesiaMachine,
  kInstrumentTable,
  kSecondaryTable,
  kMonitor,
  kSurgicalLamp,
  kCArm,
  kOrClassCount = kCArm,
};

// id -> name for ids 1..kOrClassCount ("operating table", ..., "C-arm").
const std::map<int, std::string>& or_class_names();
// The people classes that look alike in gowns, caps and masks (VLM confusions happen among them).
bool is_look_alike_class(int class_id);

// Where the operation stands: it moves people, the C-arm and the lamp.
enum class OrPhase { Preparation, Surgery, Closing };
const EnumNames<OrPhase>& or_phase_names();  // preparation, surgery, closing
const std::string& to_string(OrPhase phase);
// Throws std::invalid_argument naming the accepted values.
OrPhase parse_or_phase(const std::string& name);

struct OrSceneOptions {
  uint64_t seed = 0;  // layout variation (positions, sides, heights, extra monitor)
  OrPhase phase = OrPhase::Surgery;
  int views = 5;    // cameras, 4..8, spread over the room's corners and walls
  int width = 640;  // image size in pixels
  int height = 480;
  double horizontal_fov_deg = 75;  // wide-angle ceiling cameras
};

struct PointLight {
  Eigen::Vector3f position;
  float intensity = 0.4f;  // Lambert weight at normal incidence (no distance falloff)
};

struct OrCamera {
  std::string name;  // "cam_00", ...
  Camera camera;
  Pose pose;  // world -> camera, exact
  bool held_out = false;
};

struct OrScene {
  std::vector<Primitive> primitives;
  std::map<int, int> instance_class;  // instance id -> class id (ids 1..M)
  std::vector<PointLight> lights;
  std::vector<OrCamera> cameras;
  Eigen::Vector3f look_at = Eigen::Vector3f::Zero();  // the point all cameras aim at
};

// Deterministic in options: the same options give the same scene on every machine.
// Throws std::invalid_argument for views outside 4..8 or a non-positive image size.
OrScene make_or_scene(const OrSceneOptions& options);
// Throws std::invalid_argument when the options are outside what make_or_scene builds (4 to 8
// views, images of at least 16 x 16).
void check_or_scene_options(const OrSceneOptions& options);

// Number of held-out (test) views for a capture of n views: LangOR's 4 train : 1 test, at least 1.
int held_out_count(int views);

}  // namespace gslift::synth
