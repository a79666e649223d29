// The repo's white furnace, scenes/white_box.gltf, with its one material's albedo and emission
// set in memory: the acceptance runs the furnace in the repo's box, not one built in code.
#pragma once

#include "gi/field_params.h"
#include "scene/scene.h"

namespace ddgi::test {

// Closed box x, z in [-1, 1], y in [0, 2], inward faces, every surface emitting `emission`
// (radiance) with diffuse albedo `albedo`, so the radiance everywhere inside is
// emission / (1 - albedo). Fails the calling test when the file does not load as described.
Scene load_white_box(float albedo, float emission);

// A 2x2x2 grid of 64-ray probes 1 m apart inside the white box, half a metre from its walls,
// where the furnace tests read the field.
IrradianceFieldParams white_box_grid();

}  // namespace ddgi::test
