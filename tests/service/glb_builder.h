// Builds small .glb files in memory for upload tests: a valid one (a lit floor) and ways to
// break it.
#pragma once

#include <string>

namespace ddgi::test {

// A binary glTF with one quad (two triangles, 1x1 m at y=0) and one point light above it.
std::string make_floor_glb();

}  // namespace ddgi::test
