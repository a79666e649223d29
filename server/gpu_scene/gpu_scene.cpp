#include "gpu_scene/gpu_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_inverse.hpp>

#include "core/log.h"
#include "gpu_scene/emitter_table.h"

namespace ddgi {
namespace {

// Every scene's set 0 has this layout, so kernels built once serve any scene.
constexpr uint32_t kMaxSceneTextures = 4096;
// Instance moves remembered for fields that catch up on them (GpuScene::moved_regions).
constexpr size_t kMaxLoggedMoves = 1024;

constexpr VkBufferUsageFlags kGeometryUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR;
constexpr VkBufferUsageFlags kTableUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

template <typename T>
std::span<const uint8_t> as_bytes(const std::vector<T>& v) {
  return {reinterpret_cast<const uint8_t*>(v.data()), v.size() * sizeof(T)};
}
template <typename T>
std::span<const uint8_t> as_bytes(const T& v) {
  return {reinterpret_cast<const uint8_t*>(&v), sizeof(T)};
}

// GpuLight::type holds the scene's LightType as the scene_data.h constants.
static_assert(uint32_t(LightType::kPoint) == gpu::kLightPoint);
static_assert(uint32_t(LightType::kSpot) == gpu::kLightSpot);
static_assert(uint32_t(LightType::kDirectional) == gpu::kLightDirectional);

gpu::GpuLight to_gpu_light(const Light& light) {
  gpu::GpuLight g{};
  g.position = light.position;
  g.type = static_cast<uint32_t>(light.type);
  g.direction =
      glm::length(light.direction) > 0.0f ? glm::normalize(light.direction) : glm::vec3(0, 0, -1);
  g.range = light.range;
  g.radiance = light.color * light.intensity;
  const float cos_outer = std::cos(light.outer_cone_angle);
  const float cos_inner = std::cos(light.inner_cone_angle);
  g.spot_scale = 1.0f / std::max(cos_inner - cos_outer, 1e-4f);
  g.spot_offset = -cos_outer * g.spot_scale;
  g.radius = light.radius;
  return g;
}

}  // namespace

std::vector<vk::Binding> scene_bindings(uint32_t max_textures) {
  return {
      {gpu::kSceneBindingTlas, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},
      {gpu::kSceneBindingPositions, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingAttributes, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingIndices, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingGeometries, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingInstances, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingMaterials, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingLights, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingGlobals, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingEnvironment, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {gpu::kSceneBindingEmitters, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {gpu::kSceneBindingTextures, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, max_textures, true},
  };
}

Result<std::unique_ptr<GpuScene>> GpuScene::create(vk::Context& context, const Scene& scene) {
  if (scene.textures.size() > kMaxSceneTextures) {
    return invalid_argument(scene.source + ": " + std::to_string(scene.textures.size()) +
                            " textures; at most " + std::to_string(kMaxSceneTextures) +
                            " are supported");
  }
  std::unique_ptr<GpuScene> gpu(new GpuScene(context));
  gpu->scene_ = scene;
  gpu->bounds_ = scene.world_bounds();
  for (const Mesh& mesh : scene.meshes) {
    Bounds local;
    for (const Primitive& prim : mesh.primitives) {
      for (const glm::vec3& p : prim.positions) local.grow(p);
    }
    gpu->mesh_bounds_.push_back(local);
  }
  const uint64_t before = context.allocated_bytes();
  DDGI_TRY(gpu->upload_geometry());
  DDGI_TRY(gpu->upload_materials());
  DDGI_TRY(gpu->upload_textures());
  DDGI_TRY(gpu->upload_environment());
  DDGI_TRY(gpu->upload_lights());
  DDGI_TRY(gpu->upload_instances());
  DDGI_TRY(gpu->upload_emitters());
  DDGI_TRY(gpu->upload_globals());
  DDGI_TRY(gpu->build_acceleration_structures());
  DDGI_TRY(gpu->create_descriptors());
  gpu->gpu_bytes_ = context.allocated_bytes() - before;
  context.collect_garbage();  // staging buffers and scratch memory
  return gpu;
}

Status GpuScene::upload_geometry() {
  std::vector<glm::vec3> positions;
  std::vector<gpu::VertexAttributes> attributes;
  std::vector<uint32_t> indices;
  std::vector<gpu::GpuGeometry> geometries;
  mesh_ranges_.resize(scene_.meshes.size());
  mesh_first_geometry_.resize(scene_.meshes.size());
  for (size_t m = 0; m < scene_.meshes.size(); ++m) {
    mesh_first_geometry_[m] = static_cast<uint32_t>(geometries.size());
    for (const Primitive& prim : scene_.meshes[m].primitives) {
      PrimitiveRange range;
      range.first_vertex = static_cast<uint32_t>(positions.size());
      range.vertex_count = static_cast<uint32_t>(prim.positions.size());
      range.first_index = static_cast<uint32_t>(indices.size());
      range.index_count = static_cast<uint32_t>(prim.indices.size() / 3 * 3);
      range.material = prim.material >= 0 ? static_cast<uint32_t>(prim.material)
                                          : static_cast<uint32_t>(scene_.materials.size());
      const Material fallback;
      const Material& material = prim.material >= 0 ? scene_.materials[prim.material] : fallback;
      if (material.alpha_mode != AlphaMode::kOpaque) range.flags |= gpu::kGeometryAlphaMask;
      if (material.transmission > 0.0f) range.flags |= gpu::kGeometryTransmissive;
      if (!prim.normals.empty()) range.flags |= gpu::kGeometryHasNormals;
      if (material.double_sided) range.flags |= gpu::kGeometryDoubleSided;
      if (range.flags & gpu::kGeometryAlphaMask) scene_flags_ |= gpu::kSceneHasAlphaMask;
      if (range.flags & gpu::kGeometryTransmissive) scene_flags_ |= gpu::kSceneHasTransmission;

      // The texcoord set the base colour texture reads (emissive shares it).
      const std::vector<glm::vec2>& uvs =
          material.base_color_texcoord == 1 && !prim.texcoords1.empty() ? prim.texcoords1
                                                                        : prim.texcoords0;
      positions.insert(positions.end(), prim.positions.begin(), prim.positions.end());
      for (size_t v = 0; v < prim.positions.size(); ++v) {
        gpu::VertexAttributes a{};
        a.normal = prim.normals.empty() ? glm::vec3(0.0f) : prim.normals[v];
        a.uv = v < uvs.size() ? uvs[v] : glm::vec2(0.0f);
        attributes.push_back(a);
      }
      indices.insert(indices.end(), prim.indices.begin(), prim.indices.begin() + range.index_count);
      geometries.push_back({range.first_index, range.first_vertex, range.material, range.flags});
      mesh_ranges_[m].push_back(range);
    }
  }
  DDGI_ASSIGN_OR_RETURN(
      positions_, vk::upload_vector<glm::vec3>(context_, positions, kGeometryUsage, "positions"));
  DDGI_ASSIGN_OR_RETURN(
      attributes_, vk::upload_vector<gpu::VertexAttributes>(
                       context_, attributes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "attributes"));
  DDGI_ASSIGN_OR_RETURN(indices_,
                        vk::upload_vector<uint32_t>(context_, indices, kGeometryUsage, "indices"));
  DDGI_ASSIGN_OR_RETURN(geometries_, vk::upload_vector<gpu::GpuGeometry>(
                                         context_, geometries, kTableUsage, "geometries"));
  return ok_status();
}

Status GpuScene::upload_materials() {
  std::vector<gpu::GpuMaterial> materials;
  // One more than the scene has: the default material of primitives without one.
  std::vector<Material> all = scene_.materials;
  all.push_back(Material{});
  for (const Material& m : all) {
    gpu::GpuMaterial g{};
    g.base_color = m.base_color;
    g.emissive = m.emissive;
    g.base_color_texture = m.base_color_texture;
    g.emissive_texture = m.emissive_texture;
    // BLEND is treated as a cut-out at 0.5: a tracer has no draw order to blend in.
    g.alpha_cutoff = m.alpha_mode == AlphaMode::kBlend ? 0.5f : m.alpha_cutoff;
    g.transmission = m.transmission;
    materials.push_back(g);
  }
  DDGI_ASSIGN_OR_RETURN(materials_, vk::upload_vector<gpu::GpuMaterial>(context_, materials,
                                                                        kTableUsage, "materials"));
  return ok_status();
}

Status GpuScene::upload_textures() {
  DDGI_ASSIGN_OR_RETURN(
      texture_sampler_,
      vk::Sampler::create(context_, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_REPEAT,
                          VK_SAMPLER_ADDRESS_MODE_REPEAT, "texture sampler"));
  std::vector<Texture> textures = scene_.textures;
  if (textures.empty()) {
    // The texture array needs one valid element even when nothing samples it.
    Texture white;
    white.name = "white";
    white.width = white.height = 1;
    white.rgba8 = {255, 255, 255, 255};
    textures.push_back(white);
  }
  for (const Texture& t : textures) {
    const VkFormat format = t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
    DDGI_ASSIGN_OR_RETURN(vk::Image image, vk::Image::create_2d(context_, t.width, t.height, format,
                                                                VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                    VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                                                "texture " + t.name));
    DDGI_TRY(vk::upload_image(context_, image, t.rgba8, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL));
    textures_.push_back(std::move(image));
  }
  return ok_status();
}

Status GpuScene::upload_environment() {
  // Wraps around in longitude, clamps at the poles.
  DDGI_ASSIGN_OR_RETURN(
      environment_sampler_,
      vk::Sampler::create(context_, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_REPEAT,
                          VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE, "environment sampler"));
  const auto& image = scene_.environment.image;
  const uint32_t width = image ? image->width : 1;
  const uint32_t height = image ? image->height : 1;
  std::vector<float> rgba(size_t(width) * height * 4, 0.0f);
  if (image) {
    for (size_t i = 0; i < size_t(width) * height; ++i) {
      for (int c = 0; c < 3; ++c) {
        const float v = image->rgb[i * 3 + c];
        rgba[i * 4 + c] = std::isfinite(v) && v > 0.0f ? v : 0.0f;
      }
      rgba[i * 4 + 3] = 1.0f;
    }
  }
  DDGI_ASSIGN_OR_RETURN(
      environment_,
      vk::Image::create_2d(context_, width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                           "environment map"));
  return vk::upload_image(context_, environment_,
                          {reinterpret_cast<const uint8_t*>(rgba.data()), rgba.size() * 4},
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

Status GpuScene::upload_lights() {
  std::vector<gpu::GpuLight> lights;
  for (const Light& light : scene_.lights) lights.push_back(to_gpu_light(light));
  const size_t needed = std::max<size_t>(1, lights.size()) * sizeof(gpu::GpuLight);
  if (!lights_ || lights_.size() < needed) {
    DDGI_ASSIGN_OR_RETURN(lights_, vk::Buffer::create(context_, needed, kTableUsage,
                                                      vk::MemoryUsage::kDeviceLocal, "lights"));
    if (set_) {
      vk::DescriptorWriter(set_).buffer(gpu::kSceneBindingLights, lights_).apply(context_.device());
    }
  }
  return vk::update_buffer(context_, lights_, as_bytes(lights));
}

Status GpuScene::upload_instances() {
  std::vector<gpu::GpuInstance> instances;
  for (const Instance& inst : scene_.instances) {
    gpu::GpuInstance g{};
    g.object_to_world = inst.transform;
    g.normal_to_world = glm::mat4(glm::inverseTranspose(glm::mat3(inst.transform)));
    g.mesh = static_cast<uint32_t>(inst.mesh);
    g.first_geometry = inst.mesh >= 0 ? mesh_first_geometry_[inst.mesh] : 0;
    instances.push_back(g);
  }
  if (!instances_) {
    DDGI_ASSIGN_OR_RETURN(
        instances_, vk::Buffer::create(
                        context_, std::max<size_t>(1, instances.size()) * sizeof(gpu::GpuInstance),
                        kTableUsage, vk::MemoryUsage::kDeviceLocal, "instances"));
  }
  return vk::update_buffer(context_, instances_, as_bytes(instances));
}

Status GpuScene::upload_emitters() {
  const EmitterTable table = build_emitter_table(scene_, mesh_first_geometry_);
  // Moving instances never changes which triangles emit, so the buffer keeps its size.
  if (!emitters_) {
    const size_t bytes = std::max<size_t>(1, table.emitters.size()) * sizeof(gpu::GpuEmitter);
    DDGI_ASSIGN_OR_RETURN(emitters_, vk::Buffer::create(context_, bytes, kTableUsage,
                                                        vk::MemoryUsage::kDeviceLocal, "emitters"));
  }
  emitter_count_ = static_cast<uint32_t>(table.emitters.size());
  emitter_total_weight_ = table.total_weight;
  if (table.emitters.empty()) return ok_status();
  return vk::update_buffer(context_, emitters_, as_bytes(table.emitters));
}

Status GpuScene::upload_globals() {
  gpu::SceneGlobals g{};
  const Environment& env = scene_.environment;
  g.environment_color = env.color * env.intensity;
  g.environment_has_map = env.image ? 1u : 0u;
  g.environment_intensity = env.intensity;
  g.environment_rotation = env.rotation_y;
  g.light_count = static_cast<uint32_t>(scene_.lights.size());
  g.flags = scene_flags_;
  g.bounds_min = bounds_.empty() ? glm::vec3(0.0f) : bounds_.min;
  g.bounds_max = bounds_.empty() ? glm::vec3(0.0f) : bounds_.max;
  g.scene_scale = std::max(glm::length(bounds_.extent()), 1e-6f);
  g.ray_epsilon = g.scene_scale * 1e-5f;
  g.emitter_count = emitter_count_;
  g.emitter_total_weight = emitter_total_weight_;
  if (!globals_) {
    DDGI_ASSIGN_OR_RETURN(globals_, vk::Buffer::create(context_, sizeof(g), kTableUsage,
                                                       vk::MemoryUsage::kDeviceLocal, "globals"));
  }
  return vk::update_buffer(context_, globals_, as_bytes(g));
}

Status GpuScene::build_acceleration_structures() {
  std::vector<std::vector<vk::TriangleGeometry>> meshes(scene_.meshes.size());
  for (size_t m = 0; m < scene_.meshes.size(); ++m) {
    for (const PrimitiveRange& r : mesh_ranges_[m]) {
      vk::TriangleGeometry g;
      g.positions = positions_.address() + VkDeviceAddress(r.first_vertex) * sizeof(glm::vec3);
      g.vertex_count = r.vertex_count;
      g.indices = indices_.address() + VkDeviceAddress(r.first_index) * sizeof(uint32_t);
      g.triangle_count = r.index_count / 3;
      g.opaque = (r.flags & (gpu::kGeometryAlphaMask | gpu::kGeometryTransmissive)) == 0;
      meshes[m].push_back(g);
    }
  }
  vk::AccelerationBuilder builder(context_);
  DDGI_ASSIGN_OR_RETURN(blases_, builder.build_blases(meshes, "mesh"));
  triangle_count_ = 0;
  for (const Instance& inst : scene_.instances) {
    if (inst.mesh < 0) continue;
    for (const PrimitiveRange& r : mesh_ranges_[inst.mesh]) triangle_count_ += r.index_count / 3;
  }
  return rebuild_tlas();
}

Status GpuScene::rebuild_tlas() {
  std::vector<vk::TlasInstance> instances;
  for (size_t i = 0; i < scene_.instances.size(); ++i) {
    const Instance& inst = scene_.instances[i];
    if (inst.mesh < 0 || mesh_ranges_[inst.mesh].empty()) continue;  // nothing to trace
    instances.push_back({inst.transform, static_cast<uint32_t>(i), blases_[inst.mesh].address()});
  }
  vk::AccelerationBuilder builder(context_);
  const VkAccelerationStructureKHR before = tlas_.handle();
  DDGI_TRY(builder.build_tlas(instances, tlas_, tlas_instances_, "scene TLAS"));
  if (set_ && tlas_.handle() != before) {
    vk::DescriptorWriter(set_)
        .acceleration_structure(gpu::kSceneBindingTlas, tlas_.handle())
        .apply(context_.device());
  }
  return ok_status();
}

Status GpuScene::create_descriptors() {
  DDGI_ASSIGN_OR_RETURN(layout_, vk::DescriptorLayout::create(
                                     context_, scene_bindings(kMaxSceneTextures), 1, "scene set"));
  DDGI_ASSIGN_OR_RETURN(set_, layout_.allocate(static_cast<uint32_t>(textures_.size())));
  vk::DescriptorWriter writer(set_);
  writer.acceleration_structure(gpu::kSceneBindingTlas, tlas_.handle())
      .buffer(gpu::kSceneBindingPositions, positions_)
      .buffer(gpu::kSceneBindingAttributes, attributes_)
      .buffer(gpu::kSceneBindingIndices, indices_)
      .buffer(gpu::kSceneBindingGeometries, geometries_)
      .buffer(gpu::kSceneBindingInstances, instances_)
      .buffer(gpu::kSceneBindingMaterials, materials_)
      .buffer(gpu::kSceneBindingLights, lights_)
      .buffer(gpu::kSceneBindingGlobals, globals_)
      .buffer(gpu::kSceneBindingEmitters, emitters_)
      .sampled_image(gpu::kSceneBindingEnvironment, environment_, environment_sampler_.handle());
  for (size_t i = 0; i < textures_.size(); ++i) {
    writer.sampled_image(gpu::kSceneBindingTextures, textures_[i], texture_sampler_.handle(),
                         static_cast<uint32_t>(i));
  }
  writer.apply(context_.device());
  return ok_status();
}

Bounds GpuScene::instance_bounds(size_t instance) const {
  Bounds world;
  const Instance& inst = scene_.instances[instance];
  if (inst.mesh < 0 || mesh_bounds_[inst.mesh].empty()) return world;
  const Bounds& local = mesh_bounds_[inst.mesh];
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? local.max.x : local.min.x,
                      (corner & 2) ? local.max.y : local.min.y,
                      (corner & 4) ? local.max.z : local.min.z);
    world.grow(glm::vec3(inst.transform * glm::vec4(p, 1.0f)));
  }
  return world;
}

std::vector<Bounds> GpuScene::moved_regions(uint64_t after_move, bool* everything) const {
  *everything = move_count_ - after_move > move_log_.size();
  std::vector<Bounds> regions;
  if (*everything) return regions;
  for (uint64_t i = move_log_.size() - (move_count_ - after_move); i < move_log_.size(); ++i) {
    regions.push_back(move_log_[i]);
  }
  return regions;
}

Status GpuScene::set_instance_transform(size_t instance, const glm::mat4& object_to_world) {
  if (instance >= scene_.instances.size()) {
    return invalid_argument("instance " + std::to_string(instance) +
                            " does not exist (the scene has " +
                            std::to_string(scene_.instances.size()) + ")");
  }
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(object_to_world[c][r])) {
        return invalid_argument("instance transform has a non-finite element");
      }
    }
  }
  if (std::abs(glm::determinant(glm::mat3(object_to_world))) < 1e-30f) {
    return invalid_argument("instance transform is singular");
  }
  Bounds moved = instance_bounds(instance);
  scene_.instances[instance].transform = object_to_world;
  const Bounds after = instance_bounds(instance);
  if (!after.empty()) {
    moved.grow(after.min);
    moved.grow(after.max);
  }
  move_log_.push_back(moved);
  if (move_log_.size() > kMaxLoggedMoves) move_log_.pop_front();
  ++move_count_;
  ++revision_;
  DDGI_TRY(upload_instances());
  DDGI_TRY(upload_emitters());
  DDGI_TRY(upload_globals());
  return rebuild_tlas();
}

Status GpuScene::set_lights(const std::vector<Light>& lights) {
  scene_.lights = lights;
  ++revision_;
  DDGI_TRY(upload_lights());
  return upload_globals();
}

}  // namespace ddgi
