// The repo's two-room scene (scenes/two_rooms_*.gltf) as light-leak tests use it: a probe grid
// and surface points on either side of the thin shared wall.
#pragma once

#include <vector>

#include "gi/irradiance_field.h"

namespace ddgi::test {

// scenes/two_rooms_*.gltf: shell x in [-4.1, 3.9], y in [0, 3], z in [-2, 2]; the shared wall
// spans x in [-0.01, 0.01] with a doorway at z in [-0.45, 0.45], y in [0, 2]; the lit room is
// x < 0. This grid's probes lie at x = -3.85 + 0.5 i: the nearest to the wall are at -0.35 and
// 0.15, none in it. The base DDGI field: probes on their grid points, all traced.
IrradianceFieldParams two_room_grid();

// Surface points of one room (side -1: lit, +1: dark), concentrated near the shared wall where
// leaks show: the wall itself, the floor and ceiling beside it.
std::vector<IrradianceQuery> room_points(float side);

float mean_luminance(const std::vector<glm::vec3>& values);

}  // namespace ddgi::test
