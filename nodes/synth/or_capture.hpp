// Writes an embedded OR capture to disk in the project's one capture layout
// (docs/capture_format.md): renders every view, runs the simulated upstream models and writes
// images, depth prior, ground truth, COLMAP text model, VLM replies, SAM masks and capture.yaml.
// The same settings give byte-identical files at any thread count.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "nodes/synth/or_scene.hpp"
#include "nodes/synth/render_view.hpp"
#include "nodes/synth/synth_knobs.hpp"

namespace gslift::synth {

struct OrCaptureSettings {
  OrSceneOptions scene;
  SynthPreset preset = SynthPreset::Default;  // recorded; the knobs already hold its values
  SynthKnobs knobs;
};

// Every setting as (name, value) text, in a fixed order: the capture's identity. Recorded in
// <capture>/synth.yaml and hashed into the cache key of embedded captures.
std::vector<std::pair<std::string, std::string>> settings_entries(const OrCaptureSettings& s);

// Settings from (name, value) text pairs: seed, phase, views, width, height, preset and every
// knob of synth_knob_table(). The preset is applied first, whatever its position, so explicit
// knobs always win. Throws std::invalid_argument naming the setting and what is wrong.
OrCaptureSettings make_settings(const std::vector<std::pair<std::string, std::string>>& entries);

// "or_s<seed>_<phase>", the capture's name in capture.yaml.
std::string capture_name(const OrCaptureSettings& s);

// Generates the capture into a temporary sibling of out_dir and renames it into place, so
// out_dir appears complete or not at all. out_dir must not exist or be an empty folder
// (std::invalid_argument otherwise; invalid settings throw std::invalid_argument too).
void write_or_capture(const OrCaptureSettings& settings, const std::filesystem::path& out_dir);

// The parts both layouts write (or_rig_capture.hpp writes the OR rig's).
// gt/instance/<stem>.png and gt/semantic (16-bit), gt/depth/<stem>.tiff (in the room's metres
// x `world_scale`) and gt/normal (float).
void write_ground_truth(const RenderedView& r, const std::string& stem,
                        const std::filesystem::path& dir, double world_scale = 1);
// The simulated upstream models on view `index` as rendered in `r` (the grid of the images as
// gslift loads them): vlm/<stem>/round_<k>.txt, sam_box/<stem>/round_<k>.json,
// sam_auto/<stem>.json.
void write_model_outputs(const OrCaptureSettings& s, const OrScene& scene, int index,
                         const RenderedView& r, const std::string& stem,
                         const std::filesystem::path& dir);
// capture.yaml (its `layout` lines name the views; held_out by view_name(camera index)),
// gt/classes.yaml, vlm/prompt.txt and synth.yaml.
void write_capture_files(const OrCaptureSettings& s, const OrScene& scene,
                         const std::string& layout,
                         const std::function<std::string(int)>& view_name,
                         const std::filesystem::path& dir);
// Runs write(tmp) on a temporary sibling of out_dir and renames it into place, so out_dir
// appears complete or not at all; out_dir must not exist or be empty (std::invalid_argument).
void write_folder_atomically(const std::filesystem::path& out_dir,
                             const std::function<void(const std::filesystem::path&)>& write);

}  // namespace gslift::synth
