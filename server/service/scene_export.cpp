#include "service/scene_export.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <sstream>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "encode/jpeg.h"
#include "encode/png.h"

namespace ddgi::service {
namespace {

constexpr int kJpegQuality = 92;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// The model under construction and its one binary buffer.
struct Builder {
  tinygltf::Model model;
  std::vector<uint8_t>& bin() { return model.buffers[0].data; }

  // Appends `bytes` (4-byte aligned) as a buffer view; returns its index.
  int view(const void* bytes, size_t size, int target) {
    auto& data = bin();
    data.resize((data.size() + 3) & ~size_t(3));
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    data.insert(data.end(), static_cast<const uint8_t*>(bytes),
                static_cast<const uint8_t*>(bytes) + size);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size() - 1);
  }

  template <typename T>
  int accessor(const std::vector<T>& values, int component, int type, int target) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view(values.data(), values.size() * sizeof(T), target);
    accessor.componentType = component;
    accessor.type = type;
    accessor.count = values.size();
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
  }

  // POSITION needs its bounds (glTF 2.0, 3.6.2.4).
  int positions(const std::vector<glm::vec3>& values) {
    const int index =
        accessor(values, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, kArrayBuffer);
    Bounds bounds;
    for (const glm::vec3& p : values) bounds.grow(p);
    model.accessors[size_t(index)].minValues = {bounds.min.x, bounds.min.y, bounds.min.z};
    model.accessors[size_t(index)].maxValues = {bounds.max.x, bounds.max.y, bounds.max.z};
    return index;
  }
};

tinygltf::Primitive export_primitive(Builder& b, const Primitive& primitive) {
  tinygltf::Primitive out;
  out.mode = TINYGLTF_MODE_TRIANGLES;
  out.material = primitive.material;
  out.attributes["POSITION"] = b.positions(primitive.positions);
  if (!primitive.normals.empty()) {
    out.attributes["NORMAL"] = b.accessor(primitive.normals, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                          TINYGLTF_TYPE_VEC3, kArrayBuffer);
  }
  if (!primitive.texcoords0.empty()) {
    out.attributes["TEXCOORD_0"] = b.accessor(primitive.texcoords0, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                              TINYGLTF_TYPE_VEC2, kArrayBuffer);
  }
  if (!primitive.texcoords1.empty()) {
    out.attributes["TEXCOORD_1"] = b.accessor(primitive.texcoords1, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                              TINYGLTF_TYPE_VEC2, kArrayBuffer);
  }
  out.indices = b.accessor(primitive.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                           TINYGLTF_TYPE_SCALAR, kElementArrayBuffer);
  return out;
}

// Whether any material that uses texture `index` as its base colour reads its alpha.
bool alpha_used(const Scene& scene, int index) {
  return std::any_of(scene.materials.begin(), scene.materials.end(), [&](const Material& m) {
    return m.base_color_texture == index && m.alpha_mode != AlphaMode::kOpaque;
  });
}

Status export_images(Builder& b, const Scene& scene) {
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& texture = scene.textures[i];
    const encode::ImageRgba8 image{texture.width, texture.height, texture.rgba8};
    const bool png = alpha_used(scene, int(i));
    auto bytes = png ? encode::encode_png(image) : encode::encode_jpeg(image, kJpegQuality);
    if (!bytes.ok()) {
      return internal_error("texture " + std::to_string(i) + " ('" + texture.name +
                            "'): " + bytes.error().message);
    }
    tinygltf::Image out;
    out.name = texture.name;
    out.mimeType = png ? "image/png" : "image/jpeg";
    out.bufferView = b.view(bytes->data(), bytes->size(), 0);
    b.model.images.push_back(out);
    tinygltf::Texture gltf_texture;
    gltf_texture.source = int(i);
    gltf_texture.sampler = 0;
    b.model.textures.push_back(gltf_texture);
  }
  tinygltf::Sampler sampler;  // what the server samples with: linear, mipmapped, repeat
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  b.model.samplers.push_back(sampler);
  return ok_status();
}

tinygltf::Material export_material(const Material& m) {
  tinygltf::Material out;
  out.name = m.name;
  out.pbrMetallicRoughness.baseColorFactor = {m.base_color.r, m.base_color.g, m.base_color.b,
                                              m.base_color.a};
  out.pbrMetallicRoughness.baseColorTexture.index = m.base_color_texture;
  out.pbrMetallicRoughness.baseColorTexture.texCoord = m.base_color_texcoord;
  out.pbrMetallicRoughness.metallicFactor = 0.0;  // the server's surfaces are Lambertian
  out.pbrMetallicRoughness.roughnessFactor = 1.0;
  // emissiveFactor is limited to [0, 1]: anything brighter goes into the strength extension.
  const float strength = std::max({m.emissive.r, m.emissive.g, m.emissive.b, 1.0f});
  const glm::vec3 factor = m.emissive / strength;
  out.emissiveFactor = {factor.r, factor.g, factor.b};
  if (strength > 1.0f) {
    tinygltf::Value::Object ext{{"emissiveStrength", tinygltf::Value(double(strength))}};
    out.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(ext);
  }
  out.emissiveTexture.index = m.emissive_texture;
  out.emissiveTexture.texCoord = m.emissive_texcoord;
  out.alphaMode = m.alpha_mode == AlphaMode::kMask    ? "MASK"
                  : m.alpha_mode == AlphaMode::kBlend ? "BLEND"
                                                      : "OPAQUE";
  out.alphaCutoff = m.alpha_cutoff;
  out.doubleSided = m.double_sided;
  if (m.transmission > 0.0f) {
    tinygltf::Value::Object ext{{"transmissionFactor", tinygltf::Value(double(m.transmission))}};
    out.extensions["KHR_materials_transmission"] = tinygltf::Value(ext);
  }
  return out;
}

// A light node: at the light's position, its -Z turned onto the light's direction.
tinygltf::Node light_node(const Light& light, int index, uint32_t id) {
  tinygltf::Node node;
  node.name = light.name;
  const glm::vec3 forward = glm::normalize(light.direction);
  const glm::vec3 helper = std::abs(forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  const glm::vec3 x = glm::normalize(glm::cross(helper, -forward));
  const glm::vec3 y = glm::cross(-forward, x);
  const glm::mat4 m(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(-forward, 0.0f),
                    glm::vec4(light.position, 1.0f));
  node.matrix.assign(glm::value_ptr(m), glm::value_ptr(m) + 16);
  node.extensions["KHR_lights_punctual"] =
      tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(index)}});
  node.extras =
      tinygltf::Value(tinygltf::Value::Object{{"ddgi_light_id", tinygltf::Value(int(id))}});
  return node;
}

tinygltf::Light export_light(const Light& light) {
  tinygltf::Light out;
  out.name = light.name;
  out.color = {light.color.r, light.color.g, light.color.b};
  out.intensity = light.intensity;  // W/sr or W/m^2, as the loader took glTF's units
  out.range = light.range;
  out.type = light.type == LightType::kSpot          ? "spot"
             : light.type == LightType::kDirectional ? "directional"
                                                     : "point";
  out.spot.innerConeAngle = light.inner_cone_angle;
  out.spot.outerConeAngle = light.outer_cone_angle;
  return out;
}

void export_nodes(Builder& b, const Scene& scene, const std::vector<LightSlot>& lights) {
  tinygltf::Scene root;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    tinygltf::Node node;
    node.name = instance.name;
    node.mesh = instance.mesh;
    node.extras =
        tinygltf::Value(tinygltf::Value::Object{{"ddgi_instance", tinygltf::Value(int(i))}});
    node.matrix.assign(glm::value_ptr(instance.transform), glm::value_ptr(instance.transform) + 16);
    b.model.nodes.push_back(node);
    root.nodes.push_back(int(b.model.nodes.size() - 1));
  }
  for (size_t i = 0; i < lights.size(); ++i) {
    b.model.lights.push_back(export_light(lights[i].light));
    b.model.nodes.push_back(light_node(lights[i].light, int(i), lights[i].id));
    root.nodes.push_back(int(b.model.nodes.size() - 1));
  }
  b.model.scenes.push_back(root);
  b.model.defaultScene = 0;
}

}  // namespace

Result<ExportedScene> export_glb(const Scene& scene, const std::vector<LightSlot>& lights) {
  Builder b;
  b.model.asset.version = "2.0";
  b.model.asset.generator = "ddgi-server ExportScene";
  b.model.buffers.emplace_back();
  uint64_t triangles = 0;
  for (const Mesh& mesh : scene.meshes) {
    tinygltf::Mesh gltf_mesh;
    gltf_mesh.name = mesh.name;
    for (const Primitive& primitive : mesh.primitives) {
      gltf_mesh.primitives.push_back(export_primitive(b, primitive));
    }
    b.model.meshes.push_back(gltf_mesh);
  }
  for (const Instance& instance : scene.instances) {
    for (const Primitive& p : scene.meshes[size_t(instance.mesh)].primitives) {
      triangles += p.indices.size() / 3;
    }
  }
  DDGI_TRY(export_images(b, scene));
  for (const Material& material : scene.materials) {
    b.model.materials.push_back(export_material(material));
  }
  export_nodes(b, scene, lights);
  for (const tinygltf::Material& material : b.model.materials) {
    for (const auto& extension : material.extensions) {
      auto& used = b.model.extensionsUsed;
      if (std::find(used.begin(), used.end(), extension.first) == used.end()) {
        used.push_back(extension.first);
      }
    }
  }
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&b.model, stream, false, true)) {
    return internal_error("the scene could not be written as glTF");
  }
  const std::string bytes = stream.str();
  ExportedScene out;
  out.glb.assign(bytes.begin(), bytes.end());
  out.metadata.set_total_bytes(out.glb.size());
  out.metadata.set_triangles(uint32_t(std::min<uint64_t>(triangles, UINT32_MAX)));
  out.metadata.set_instances(uint32_t(scene.instances.size()));
  out.metadata.set_textures(uint32_t(scene.textures.size()));
  out.metadata.set_lights(uint32_t(lights.size()));
  return out;
}

}  // namespace ddgi::service
