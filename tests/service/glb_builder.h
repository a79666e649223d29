// Builds .glb files in memory for upload tests: a lit floor of one quad or of many.
#pragma once

#include <cstdint>
#include <string>

namespace ddgi::test {

// A binary glTF with one quad (two triangles, 1x1 m at y=0) and one point light above it.
std::string make_floor_glb();

// The same floor made of cells x cells quads (2 cells^2 triangles, 32-bit indices): about
// 28 cells^2 bytes, a scene whose size the test chooses.
std::string make_grid_glb(uint32_t cells);

}  // namespace ddgi::test
