// Scenes built in code for GPU tests: exact, tiny, and independent of the glTF loader.
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace ddgi::test {

// Adds a material and returns its index.
int add_material(Scene& scene, glm::vec3 albedo, glm::vec3 emissive = glm::vec3(0.0f),
                 const std::string& name = "");

// Adds a mesh with one quad (two triangles, corners counter-clockwise seen from the front)
// and an instance of it; returns the instance index.
int add_quad(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, int material,
             bool with_normals = true);

// Adds a closed axis-aligned box (outward faces) as one mesh and one instance placed by
// `transform`; the box spans [-0.5, 0.5]^3 in object space. Returns the instance index.
int add_box(Scene& scene, const glm::mat4& transform, int material);

// A Cornell-like box: 2 m room (x, z in [-1, 1], y in [0, 2]), open at +z, red left and green
// right walls, a tall and a short box, a point light under the ceiling, camera in front.
Scene make_cornell_box();

// A corridor 6 m long (x in [-3, 3]), 2 m wide (z) and high (y), closed, red and green side
// walls, lit by three point lights under its ceiling at x = -2, 0, 2: long enough for a camera
// to travel through a field smaller than it, plain enough that the view changes smoothly.
Scene make_corridor();

// Scales a scene uniformly about the origin: instances, lights (point/spot intensity by s^2,
// so irradiance at corresponding points is unchanged), cameras. Physics says every radiance
// stays the same.
void scale_scene(Scene& scene, float s);

// A closed box (inward faces) with every surface emitting `emission` with albedo `albedo`.
Scene make_white_furnace_box(float albedo, float emission);

}  // namespace ddgi::test
