// Textureless sterile drapes over the operating-room equipment: a failure knob of the embedded OR
// (issue 15's stability matrix). In a real OR the C-arm, the tables and often the machines are
// covered in uniform blue or green cloth: photometric reconstruction sees no texture there, SfM
// finds no features (so the sparse points leave those surfaces), and the drapes look like the
// staff's gowns.
#pragma once

#include <cstdint>
#include <set>

#include "nodes/synth/or_scene.hpp"

namespace gslift::synth {

// The sterile blue of drapes and gowns (a flat material: no texture at all).
Material drape_material();

// Covers round(fraction * n) of the scene's n equipment instances (every class that is not a
// person, the patient or the lamp), chosen by a seeded shuffle of its own random stream, in
// drape_material(); returns their instance ids. Geometry, ids and every other random draw of the
// capture are unchanged; fraction 0 changes nothing. Throws std::invalid_argument outside [0, 1].
std::set<int> drape_equipment(OrScene& scene, double fraction, uint64_t seed);

}  // namespace gslift::synth
