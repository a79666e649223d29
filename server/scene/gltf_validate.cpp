#include "scene/gltf_validate.h"

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "scene/accessor_reader.h"
#include "scene/finite.h"
#include "scene/gltf_values.h"

namespace ddgi {
namespace {

std::string at(const char* array, size_t index) {
  return std::string(array) + "[" + std::to_string(index) + "]";
}

// An index field: -1 (absent) when `optional`, else [0, size).
Status check_ref(int value, size_t size, const std::string& field, const char* target,
                 bool optional = true) {
  if (optional && value == -1) return ok_status();
  if (value < 0 || static_cast<size_t>(value) >= size) {
    return invalid_argument(field + " = " + std::to_string(value) +
                            " does not exist (the file has " + std::to_string(size) + " " + target +
                            ")");
  }
  return ok_status();
}

Status check_finite(const std::vector<double>& values, const std::string& field) {
  for (double v : values) {
    if (!finite_as_float(v)) {
      return invalid_argument(field + " contains a value that is not finite or beyond float range");
    }
  }
  return ok_status();
}

Status check_length(const std::vector<double>& values, std::initializer_list<size_t> allowed,
                    const std::string& field) {
  for (size_t n : allowed) {
    if (values.size() == n) return check_finite(values, field);
  }
  return invalid_argument(field + " has " + std::to_string(values.size()) +
                          " values, which is not a valid length");
}

Status check_required_extensions(const tinygltf::Model& model) {
  static const std::set<std::string> kSupported = {
      "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission",
      "KHR_mesh_quantization"};
  for (const std::string& name : model.extensionsRequired) {
    if (!kSupported.contains(name)) {
      return invalid_argument("extensionsRequired lists '" + name +
                              "', which this loader does not support");
    }
  }
  return ok_status();
}

Status check_buffers(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.bufferViews.size(); ++i) {
    DDGI_TRY(buffer_view_bytes(model, static_cast<int>(i)));
  }
  for (size_t i = 0; i < model.accessors.size(); ++i) {
    DDGI_TRY(describe_accessor(model, static_cast<int>(i)));
  }
  return ok_status();
}

Status check_meshes(const tinygltf::Model& model) {
  for (size_t m = 0; m < model.meshes.size(); ++m) {
    const auto& primitives = model.meshes[m].primitives;
    for (size_t p = 0; p < primitives.size(); ++p) {
      const tinygltf::Primitive& prim = primitives[p];
      const std::string where = at("meshes", m) + "." + at("primitives", p);
      for (const auto& [name, accessor] : prim.attributes) {
        DDGI_TRY(check_ref(accessor, model.accessors.size(), where + ".attributes." + name,
                           "accessors", false));
      }
      DDGI_TRY(check_ref(prim.indices, model.accessors.size(), where + ".indices", "accessors"));
      DDGI_TRY(check_ref(prim.material, model.materials.size(), where + ".material", "materials"));
      if (prim.mode < TINYGLTF_MODE_POINTS || prim.mode > TINYGLTF_MODE_TRIANGLE_FAN) {
        return invalid_argument(where + ".mode " + std::to_string(prim.mode) +
                                " is not a glTF primitive mode (0..6)");
      }
    }
  }
  return ok_status();
}

Status check_texture_info(const tinygltf::Model& model, int index, int texcoord,
                          const std::string& where) {
  DDGI_TRY(check_ref(index, model.textures.size(), where + ".index", "textures"));
  if (texcoord < 0) {
    return invalid_argument(where + ".texCoord " + std::to_string(texcoord) + " is negative");
  }
  return ok_status();
}

Status check_materials(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& mat = model.materials[i];
    const std::string where = at("materials", i);
    const auto& pbr = mat.pbrMetallicRoughness;
    DDGI_TRY(check_texture_info(model, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                where + ".pbrMetallicRoughness.baseColorTexture"));
    DDGI_TRY(check_texture_info(model, pbr.metallicRoughnessTexture.index,
                                pbr.metallicRoughnessTexture.texCoord,
                                where + ".pbrMetallicRoughness.metallicRoughnessTexture"));
    DDGI_TRY(check_texture_info(model, mat.normalTexture.index, mat.normalTexture.texCoord,
                                where + ".normalTexture"));
    DDGI_TRY(check_texture_info(model, mat.occlusionTexture.index, mat.occlusionTexture.texCoord,
                                where + ".occlusionTexture"));
    DDGI_TRY(check_texture_info(model, mat.emissiveTexture.index, mat.emissiveTexture.texCoord,
                                where + ".emissiveTexture"));
    DDGI_TRY(
        check_length(pbr.baseColorFactor, {4}, where + ".pbrMetallicRoughness.baseColorFactor"));
    DDGI_TRY(check_length(mat.emissiveFactor, {3}, where + ".emissiveFactor"));
    if (mat.alphaMode != "OPAQUE" && mat.alphaMode != "MASK" && mat.alphaMode != "BLEND") {
      return invalid_argument(where + ".alphaMode '" + mat.alphaMode +
                              "' is not OPAQUE, MASK or BLEND");
    }
    if (!finite_as_float(mat.alphaCutoff) || mat.alphaCutoff < 0.0) {
      return invalid_argument(where + ".alphaCutoff must be a finite number >= 0");
    }
  }
  for (size_t i = 0; i < model.textures.size(); ++i) {
    const tinygltf::Texture& tex = model.textures[i];
    DDGI_TRY(check_ref(tex.source, model.images.size(), at("textures", i) + ".source", "images"));
    DDGI_TRY(
        check_ref(tex.sampler, model.samplers.size(), at("textures", i) + ".sampler", "samplers"));
  }
  return ok_status();
}

Status check_nodes(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    const tinygltf::Node& node = model.nodes[i];
    const std::string where = at("nodes", i);
    DDGI_TRY(check_ref(node.mesh, model.meshes.size(), where + ".mesh", "meshes"));
    DDGI_TRY(check_ref(node.camera, model.cameras.size(), where + ".camera", "cameras"));
    DDGI_TRY(check_ref(node.skin, model.skins.size(), where + ".skin", "skins"));
    for (size_t c = 0; c < node.children.size(); ++c) {
      DDGI_TRY(check_ref(node.children[c], model.nodes.size(), where + "." + at("children", c),
                         "nodes", false));
    }
    DDGI_TRY(check_length(node.matrix, {0, 16}, where + ".matrix"));
    DDGI_TRY(check_length(node.translation, {0, 3}, where + ".translation"));
    DDGI_TRY(check_length(node.rotation, {0, 4}, where + ".rotation"));
    DDGI_TRY(check_length(node.scale, {0, 3}, where + ".scale"));
    const std::string ext_where = where + ".extensions.KHR_lights_punctual";
    const tinygltf::Value* light = find_extension(node.extensions, "KHR_lights_punctual");
    DDGI_ASSIGN_OR_RETURN(const std::optional<int> light_index,
                          optional_int(light, "light", ext_where));
    if (light != nullptr && !light_index) return invalid_argument(ext_where + ".light is missing");
    if (light_index) {
      DDGI_TRY(check_ref(*light_index, model.lights.size(), ext_where + ".light",
                         "KHR_lights_punctual lights", false));
    }
  }
  for (size_t s = 0; s < model.scenes.size(); ++s) {
    const auto& roots = model.scenes[s].nodes;
    for (size_t r = 0; r < roots.size(); ++r) {
      DDGI_TRY(check_ref(roots[r], model.nodes.size(), at("scenes", s) + "." + at("nodes", r),
                         "nodes", false));
    }
  }
  return check_ref(model.defaultScene, model.scenes.size(), "scene", "scenes");
}

Status check_cameras_and_lights(const tinygltf::Model& model) {
  for (size_t i = 0; i < model.cameras.size(); ++i) {
    const tinygltf::Camera& camera = model.cameras[i];
    if (camera.type != "perspective") continue;
    const std::string where = at("cameras", i) + ".perspective";
    const double yfov = camera.perspective.yfov;
    if (!finite_as_float(yfov) || yfov <= 0.0 || yfov >= M_PI) {
      return invalid_argument(where + ".yfov " + std::to_string(yfov) +
                              " must be in (0, pi) radians");
    }
    if (!finite_as_float(camera.perspective.znear) || camera.perspective.znear <= 0.0) {
      return invalid_argument(where + ".znear must be a finite number > 0");
    }
  }
  for (size_t i = 0; i < model.lights.size(); ++i) {
    const tinygltf::Light& light = model.lights[i];
    const std::string where = "extensions.KHR_lights_punctual." + at("lights", i);
    if (light.type != "point" && light.type != "spot" && light.type != "directional") {
      return invalid_argument(where + ".type '" + light.type +
                              "' is not point, spot or directional");
    }
    DDGI_TRY(check_length(light.color, {0, 3}, where + ".color"));
    for (double c : light.color) {
      if (c < 0.0) return invalid_argument(where + ".color has a negative component");
    }
    if (!finite_as_float(light.intensity) || light.intensity < 0.0) {
      return invalid_argument(where + ".intensity must be a finite number >= 0");
    }
    if (!finite_as_float(light.range) || light.range < 0.0) {
      return invalid_argument(where + ".range must be a finite number > 0 (or absent)");
    }
    if (light.type == "spot") {
      const double inner = light.spot.innerConeAngle;
      const double outer = light.spot.outerConeAngle;
      // The spec wants inner < outer; inner == outer (a hard edge) is common in exports and
      // harmless, so it passes.
      if (!finite_as_float(inner) || !finite_as_float(outer) || inner < 0.0 || inner > outer ||
          outer <= 0.0 || outer > M_PI / 2 + 1e-6) {
        return invalid_argument(where + ".spot cone angles (inner " + std::to_string(inner) +
                                ", outer " + std::to_string(outer) +
                                ") must satisfy 0 <= inner <= outer <= pi/2, outer > 0");
      }
    }
  }
  return ok_status();
}

}  // namespace

Status validate_gltf(const tinygltf::Model& model) {
  DDGI_TRY(check_required_extensions(model));
  DDGI_TRY(check_buffers(model));
  DDGI_TRY(check_meshes(model));
  DDGI_TRY(check_materials(model));
  DDGI_TRY(check_nodes(model));
  DDGI_TRY(check_cameras_and_lights(model));
  return ok_status();
}

}  // namespace ddgi
