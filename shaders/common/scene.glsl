// Scene resources (descriptor set 0) and surface reconstruction at a hit.
#ifndef DDGI_COMMON_SCENE_GLSL
#define DDGI_COMMON_SCENE_GLSL

#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_nonuniform_qualifier : require

#include "shared/scene_data.h"
#include "common/math.glsl"

layout(set = kSceneSet, binding = kSceneBindingTlas) uniform accelerationStructureEXT scene_tlas;
layout(set = kSceneSet, binding = kSceneBindingPositions, scalar) readonly buffer ScenePositions {
  vec3 scene_positions[];
};
layout(set = kSceneSet, binding = kSceneBindingAttributes, scalar) readonly buffer SceneAttributes {
  VertexAttributes scene_attributes[];
};
layout(set = kSceneSet, binding = kSceneBindingIndices, scalar) readonly buffer SceneIndices {
  uint scene_indices[];
};
layout(set = kSceneSet, binding = kSceneBindingGeometries, scalar) readonly buffer SceneGeometries {
  GpuGeometry scene_geometries[];
};
layout(set = kSceneSet, binding = kSceneBindingInstances, scalar) readonly buffer SceneInstances {
  GpuInstance scene_instances[];
};
layout(set = kSceneSet, binding = kSceneBindingMaterials, scalar) readonly buffer SceneMaterials {
  GpuMaterial scene_materials[];
};
layout(set = kSceneSet, binding = kSceneBindingLights, scalar) readonly buffer SceneLights {
  GpuLight scene_lights[];
};
layout(set = kSceneSet, binding = kSceneBindingGlobals, scalar) readonly buffer SceneGlobalsBlock {
  SceneGlobals scene;
};
layout(set = kSceneSet, binding = kSceneBindingEnvironment) uniform sampler2D environment_map;
layout(set = kSceneSet, binding = kSceneBindingTextures) uniform sampler2D scene_textures[];
layout(set = kSceneSet, binding = kSceneBindingEmitters, scalar) readonly buffer SceneEmitters {
  GpuEmitter scene_emitters[];
};

// A ray's closest hit; t < 0 means the ray missed everything.
struct Hit {
  float t;
  uint instance;   // our instance table index (gl_InstanceCustomIndexEXT)
  uint geometry;   // geometry index inside the instance's BLAS
  uint primitive;  // triangle index inside the geometry
  vec2 barycentrics;
  vec3 transmittance;  // of the thin glass crossed before the hit (before tmax on a miss)
};

Hit miss_hit() {
  Hit h;
  h.t = -1.0;
  h.instance = 0u;
  h.geometry = 0u;
  h.primitive = 0u;
  h.barycentrics = vec2(0.0);
  h.transmittance = vec3(1.0);
  return h;
}

GpuGeometry geometry_of(uint instance, uint geometry) {
  return scene_geometries[scene_instances[nonuniformEXT(instance)].first_geometry + geometry];
}

uvec3 triangle_vertices(GpuGeometry geo, uint primitive) {
  const uint base = geo.first_index + 3u * primitive;
  return uvec3(scene_indices[base], scene_indices[base + 1u], scene_indices[base + 2u]) +
         geo.first_vertex;
}

vec2 interpolate_uv(uvec3 v, vec2 bary) {
  const vec3 w = vec3(1.0 - bary.x - bary.y, bary.x, bary.y);
  return scene_attributes[v.x].uv * w.x + scene_attributes[v.y].uv * w.y +
         scene_attributes[v.z].uv * w.z;
}

vec4 sample_texture(int index, vec2 uv) {
  return textureLod(scene_textures[nonuniformEXT(index)], uv, 0.0);
}

// Alpha of the material at a candidate hit (alpha-masked geometry only).
float material_alpha(GpuGeometry geo, uint primitive, vec2 bary) {
  const GpuMaterial m = scene_materials[geo.material];
  float alpha = m.base_color.a;
  if (m.base_color_texture >= 0) {
    alpha *= sample_texture(m.base_color_texture, interpolate_uv(triangle_vertices(geo, primitive), bary)).a;
  }
  return alpha;
}

// Candidate handling shared by ray queries and any-hit shaders.
// Shadow rays: the fraction of light this candidate lets through (0: it blocks).
vec3 candidate_transmittance(uint instance, uint geometry, uint primitive, vec2 bary) {
  const GpuGeometry geo = geometry_of(instance, geometry);
  const GpuMaterial m = scene_materials[geo.material];
  if ((geo.flags & kGeometryTransmissive) != 0u) {
    vec3 tint = m.base_color.rgb;
    if (m.base_color_texture >= 0) {
      tint *= sample_texture(m.base_color_texture,
                             interpolate_uv(triangle_vertices(geo, primitive), bary)).rgb;
    }
    return m.transmission * tint;
  }
  if ((geo.flags & kGeometryAlphaMask) != 0u) {
    return material_alpha(geo, primitive, bary) >= m.alpha_cutoff ? vec3(0.0) : vec3(1.0);
  }
  return vec3(0.0);
}

// Closest-hit rays: whether this candidate is a surface. When it is not (thin glass, a cut-out
// texel), `passed` is the light it lets through: the glass tint, or 1.
bool candidate_is_surface(uint instance, uint geometry, uint primitive, vec2 bary,
                          out vec3 passed) {
  passed = vec3(1.0);
  const GpuGeometry geo = geometry_of(instance, geometry);
  if ((geo.flags & kGeometryTransmissive) != 0u) {
    passed = candidate_transmittance(instance, geometry, primitive, bary);
    return false;
  }
  if ((geo.flags & kGeometryAlphaMask) != 0u) {
    return material_alpha(geo, primitive, bary) >= scene_materials[geo.material].alpha_cutoff;
  }
  return true;
}

struct Surface {
  vec3 position;
  vec3 normal;            // shading normal, on the side the ray came from when double-sided
  vec3 geometric_normal;  // on the same side as `normal`
  bool front_face;        // the ray hit the front side (always true for double-sided)
  vec3 albedo;            // linear diffuse reflectance
  vec3 emission;          // emitted radiance (front faces only)
  uint material;
};

Surface surface_at(Hit hit, vec3 ray_direction) {
  const GpuInstance inst = scene_instances[hit.instance];
  const GpuGeometry geo = scene_geometries[inst.first_geometry + hit.geometry];
  const uvec3 v = triangle_vertices(geo, hit.primitive);
  const vec3 w = vec3(1.0 - hit.barycentrics.x - hit.barycentrics.y, hit.barycentrics);
  const vec3 p0 = scene_positions[v.x];
  const vec3 p1 = scene_positions[v.y];
  const vec3 p2 = scene_positions[v.z];
  const vec3 p_object = p0 * w.x + p1 * w.y + p2 * w.z;
  const mat3 normal_matrix = mat3(inst.normal_to_world);

  Surface s;
  s.position = (inst.object_to_world * vec4(p_object, 1.0)).xyz;
  s.geometric_normal = safe_normalize(normal_matrix * cross(p1 - p0, p2 - p0), vec3(0, 1, 0));
  s.front_face = dot(s.geometric_normal, ray_direction) <= 0.0;
  if ((geo.flags & kGeometryHasNormals) != 0u) {
    const vec3 n = scene_attributes[v.x].normal * w.x + scene_attributes[v.y].normal * w.y +
                   scene_attributes[v.z].normal * w.z;
    s.normal = safe_normalize(normal_matrix * n, s.geometric_normal);
  } else {
    s.normal = s.geometric_normal;
  }
  // Shade the side the ray sees; a shading normal may not point below its triangle.
  if (!s.front_face) {
    s.geometric_normal = -s.geometric_normal;
    s.normal = -s.normal;
  }
  if (dot(s.normal, s.geometric_normal) < 0.0) s.normal = s.geometric_normal;
  if ((geo.flags & kGeometryDoubleSided) != 0u) s.front_face = true;

  const GpuMaterial m = scene_materials[geo.material];
  s.material = geo.material;
  const vec2 uv = interpolate_uv(v, hit.barycentrics);
  s.albedo = m.base_color.rgb;
  if (m.base_color_texture >= 0) s.albedo *= sample_texture(m.base_color_texture, uv).rgb;
  s.emission = m.emissive;
  if (m.emissive_texture >= 0 && any(greaterThan(m.emissive, vec3(0.0)))) {
    s.emission *= sample_texture(m.emissive_texture, uv).rgb;
  }
  if (!s.front_face) s.emission = vec3(0.0);
  return s;
}

// Radiance arriving along a ray that left the scene (direction `d`, unit).
vec3 environment_radiance(vec3 d) {
  if (scene.environment_has_map == 0u) return scene.environment_color;
  const float c = cos(scene.environment_rotation);
  const float s = sin(scene.environment_rotation);
  const vec3 r = vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
  // u = atan2(-z, -x) / 2pi wrapped to [0, 1), v = acos(y) / pi with v = 0 the top row.
  float u = atan(-r.z, -r.x) * (0.5 * kInvPi);
  u = u - floor(u);
  const float v = acos(clamp(r.y, -1.0, 1.0)) * kInvPi;
  return textureLod(environment_map, vec2(u, v), 0.0).rgb * scene.environment_intensity;
}

#endif
