#include "scene/gltf_geometry.h"

#include <numeric>

#include "scene/accessor_reader.h"

namespace ddgi {
namespace {

template <typename Vec>
std::vector<Vec> to_vectors(const std::vector<float>& flat) {
  constexpr size_t kN = sizeof(Vec) / sizeof(float);
  std::vector<Vec> result(flat.size() / kN);
  for (size_t i = 0; i < result.size(); ++i) {
    for (size_t c = 0; c < kN; ++c) result[i][static_cast<int>(c)] = flat[i * kN + c];
  }
  return result;
}

// Triangle lists from the primitive's corner order (glTF 2.0 section 3.7.2.1).
std::vector<uint32_t> to_triangle_list(const std::vector<uint32_t>& corners, int mode) {
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    return std::vector<uint32_t>(corners.begin(), corners.end() - corners.size() % 3);
  }
  std::vector<uint32_t> list;
  if (corners.size() < 3) return list;
  list.reserve((corners.size() - 2) * 3);
  for (size_t i = 0; i + 2 < corners.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // Every other triangle swaps two corners to keep the winding.
      const size_t odd = i % 2;
      list.insert(list.end(), {corners[i], corners[i + 1 + odd], corners[i + 2 - odd]});
    } else {  // TRIANGLE_FAN
      list.insert(list.end(), {corners[i + 1], corners[i + 2], corners[0]});
    }
  }
  return list;
}

Result<std::vector<float>> read_attribute(const tinygltf::Model& model,
                                          const tinygltf::Primitive& prim, const std::string& name,
                                          int type, bool normalized_ints, uint64_t vertex_count,
                                          const std::string& where) {
  const auto it = prim.attributes.find(name);
  if (it == prim.attributes.end()) return std::vector<float>();
  const std::string what = where + ".attributes." + name;
  DDGI_ASSIGN_OR_RETURN(const AccessorLayout layout, describe_accessor(model, it->second));
  if (layout.count != vertex_count) {
    return invalid_argument(what + " has " + std::to_string(layout.count) +
                            " elements but POSITION has " + std::to_string(vertex_count));
  }
  return read_float_accessor(model, it->second, type, normalized_ints, vertex_count, what);
}

// Converts one primitive; an empty result (no triangles) means "skip it".
Result<Primitive> convert_primitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                    const std::string& where, GeometryBudget* budget,
                                    std::vector<std::string>* warnings) {
  Primitive out;
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
      prim.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    warnings->push_back(where + ": mode " + std::to_string(prim.mode) +
                        " (points or lines) skipped; only triangles are rendered");
    return out;
  }
  const auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) {
    warnings->push_back(where + ": no POSITION attribute; skipped");
    return out;
  }
  DDGI_ASSIGN_OR_RETURN(std::vector<float> positions,
                        read_float_accessor(model, position->second, TINYGLTF_TYPE_VEC3, false,
                                            budget->vertices_left, where + ".attributes.POSITION"));
  const uint64_t vertex_count = positions.size() / 3;
  budget->vertices_left -= vertex_count;
  DDGI_ASSIGN_OR_RETURN(
      std::vector<float> normals,
      read_attribute(model, prim, "NORMAL", TINYGLTF_TYPE_VEC3, true, vertex_count, where));
  DDGI_ASSIGN_OR_RETURN(
      std::vector<float> uv0,
      read_attribute(model, prim, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, false, vertex_count, where));
  DDGI_ASSIGN_OR_RETURN(
      std::vector<float> uv1,
      read_attribute(model, prim, "TEXCOORD_1", TINYGLTF_TYPE_VEC2, false, vertex_count, where));

  std::vector<uint32_t> corners;
  if (prim.indices >= 0) {
    // A strip or fan of n corners has n - 2 triangles; a list n / 3.
    const uint64_t max_corners = budget->triangles_left * 3 + 2;
    DDGI_ASSIGN_OR_RETURN(
        corners, read_index_accessor(model, prim.indices, max_corners, where + ".indices"));
    for (size_t i = 0; i < corners.size(); ++i) {
      if (corners[i] >= vertex_count) {
        return invalid_argument(where + ".indices: index " + std::to_string(corners[i]) +
                                " at position " + std::to_string(i) +
                                " is out of range (the primitive has " +
                                std::to_string(vertex_count) + " vertices)");
      }
    }
  } else {
    corners.resize(static_cast<size_t>(vertex_count));
    std::iota(corners.begin(), corners.end(), 0u);
  }
  if (prim.mode == TINYGLTF_MODE_TRIANGLES && corners.size() % 3 != 0) {
    warnings->push_back(where + ": " + std::to_string(corners.size()) +
                        " indices is not a multiple of 3; the incomplete last triangle is dropped");
  }
  out.indices = to_triangle_list(corners, prim.mode);
  const uint64_t triangles = out.indices.size() / 3;
  if (triangles == 0) {
    warnings->push_back(where + ": no triangles; skipped");
    return out;
  }
  if (triangles > budget->triangles_left) {
    return resource_exhausted(where + ": the scene has more than the limit of " +
                              std::to_string(budget->max_triangles) + " triangles");
  }
  budget->triangles_left -= triangles;
  out.positions = to_vectors<glm::vec3>(positions);
  out.normals = to_vectors<glm::vec3>(normals);
  out.texcoords0 = to_vectors<glm::vec2>(uv0);
  out.texcoords1 = to_vectors<glm::vec2>(uv1);
  out.material = prim.material;
  return out;
}

}  // namespace

Result<Mesh> convert_mesh(const tinygltf::Model& model, int index, GeometryBudget* budget,
                          std::vector<std::string>* warnings) {
  const tinygltf::Mesh& mesh = model.meshes[static_cast<size_t>(index)];
  Mesh out;
  out.name = mesh.name;
  for (size_t p = 0; p < mesh.primitives.size(); ++p) {
    const std::string where =
        "meshes[" + std::to_string(index) + "].primitives[" + std::to_string(p) + "]";
    DDGI_ASSIGN_OR_RETURN(Primitive prim,
                          convert_primitive(model, mesh.primitives[p], where, budget, warnings));
    if (prim.indices.empty()) continue;
    if (budget->primitives_left == 0) {
      return resource_exhausted(where + ": the scene has more than the limit of " +
                                std::to_string(budget->max_primitives) + " primitives");
    }
    --budget->primitives_left;
    out.primitives.push_back(std::move(prim));
  }
  return out;
}

}  // namespace ddgi
