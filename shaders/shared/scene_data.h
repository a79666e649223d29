// The scene as the GPU sees it: descriptor set 0 of every tracing kernel.
// Storage buffers use scalar layout (GL_EXT_scalar_block_layout), so C++ structs match
// member for member with no padding rules beyond C's own.
#ifndef DDGI_SHARED_SCENE_DATA_H
#define DDGI_SHARED_SCENE_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

// Descriptor set 0 bindings.
DDGI_CONST uint kSceneBindingTlas = 0;
DDGI_CONST uint kSceneBindingPositions = 1;  // vec3 per vertex (also the BLAS input)
DDGI_CONST uint kSceneBindingAttributes = 2;  // VertexAttributes per vertex
DDGI_CONST uint kSceneBindingIndices = 3;     // uint per triangle corner
DDGI_CONST uint kSceneBindingGeometries = 4;  // GpuGeometry per BLAS geometry
DDGI_CONST uint kSceneBindingInstances = 5;   // GpuInstance per TLAS instance
DDGI_CONST uint kSceneBindingMaterials = 6;   // GpuMaterial
DDGI_CONST uint kSceneBindingLights = 7;      // GpuLight
DDGI_CONST uint kSceneBindingGlobals = 8;     // SceneGlobals (one)
DDGI_CONST uint kSceneBindingEnvironment = 9; // equirectangular map (RGBA32F)
DDGI_CONST uint kSceneBindingEmitters = 11;   // GpuEmitter per emissive triangle (world space)
// Vulkan requires the variable-sized array to have the highest binding number, so it sits at
// the top of the range and new bindings take the free numbers below it (12..30).
DDGI_CONST uint kSceneBindingTextures = 31;   // variable-sized array, last binding

DDGI_CONST uint kSceneSet = 0;

// GpuGeometry::flags
DDGI_CONST uint kGeometryAlphaMask = 1u;      // cut out where alpha < cutoff (any-hit)
DDGI_CONST uint kGeometryTransmissive = 2u;   // thin glass: never an occluder, tints rays
DDGI_CONST uint kGeometryHasNormals = 4u;     // else shade with the face normal
DDGI_CONST uint kGeometryDoubleSided = 8u;    // back faces shade as front faces

struct VertexAttributes {
  vec3 normal;
  vec2 uv;
};

struct GpuGeometry {
  uint first_index;    // into the index buffer
  uint first_vertex;   // added to every index
  uint material;       // index into materials
  uint flags;
};

struct GpuInstance {
  mat4 object_to_world;
  mat4 normal_to_world;  // inverse transpose of the upper 3x3, in a mat4 for alignment
  uint first_geometry;   // this mesh's geometry 0 in the geometry table
  uint mesh;
  uint pad0;
  uint pad1;
};

struct GpuMaterial {
  vec4 base_color;         // linear RGBA
  vec3 emissive;           // linear radiance (factor x strength)
  int base_color_texture;  // -1: none
  int emissive_texture;    // -1: none
  float alpha_cutoff;
  float transmission;      // thin glass: rays pass, tinted by transmission x base colour
  uint pad0;
};

DDGI_CONST uint kLightPoint = 0u;
DDGI_CONST uint kLightSpot = 1u;
DDGI_CONST uint kLightDirectional = 2u;

struct GpuLight {
  vec3 position;
  uint type;
  vec3 direction;       // the direction light travels (towards the scene for directional)
  float range;          // 0: infinite
  vec3 radiance;        // colour x intensity (W/sr for point/spot, W/m^2 for directional)
  float spot_scale;     // 1 / max(cos(inner) - cos(outer), 1e-4)
  float spot_offset;    // -cos(outer) * spot_scale
  float radius;         // sphere light radius (0: a point)
  float pad0;
  float pad1;
};

struct SceneGlobals {
  vec3 environment_color;     // constant environment radiance (x intensity)
  uint environment_has_map;   // 1: sample the map, times environment_intensity
  float environment_intensity;
  float environment_rotation; // radians about +Y
  uint light_count;
  uint flags;                 // kSceneHas* below
  vec3 bounds_min;
  float scene_scale;          // length of the bounds' diagonal (ray offsets scale with it)
  vec3 bounds_max;
  float ray_epsilon;          // offset along the normal for secondary rays
  uint emitter_count;         // entries of the emitter table
  float emitter_total_weight; // sum of area x luminance(emissive factor) over emitters
};

// One emissive triangle in world space, for light sampling. Emitters are chosen with
// probability proportional to area x luminance(emission), so a point on any emitter has the
// area density luminance(emission) / SceneGlobals::emitter_total_weight.
struct GpuEmitter {
  vec3 p0;
  uint instance;   // instance table index (as in a Hit)
  vec3 p1;
  uint geometry;   // index into the geometry table (instance's first_geometry + local index)
  vec3 p2;
  uint primitive;  // triangle index inside the geometry
  vec3 normal;     // unit face normal in the convention of surface_at (the emitting side)
  float area;
  vec3 emission;   // the material's emissive factor (its texture is applied where sampled)
  float cdf;       // probability of choosing this emitter or one before it; the last is 1
};

DDGI_CONST uint kSceneHasAlphaMask = 1u;
DDGI_CONST uint kSceneHasTransmission = 2u;

#ifdef __cplusplus
// C++ only: the byte layout GLSL gives these structs (scalar block layout), member by member, so
// that the C++ and GLSL views of a struct cannot drift apart. A failure means a struct changed:
// check that the GLSL side agrees (same header), then update the numbers here.
static_assert(sizeof(VertexAttributes) == 20);
static_assert(offsetof(VertexAttributes, normal) == 0);
static_assert(offsetof(VertexAttributes, uv) == 12);

static_assert(sizeof(GpuGeometry) == 16);
static_assert(offsetof(GpuGeometry, first_index) == 0);
static_assert(offsetof(GpuGeometry, first_vertex) == 4);
static_assert(offsetof(GpuGeometry, material) == 8);
static_assert(offsetof(GpuGeometry, flags) == 12);

static_assert(sizeof(GpuInstance) == 144);
static_assert(offsetof(GpuInstance, object_to_world) == 0);
static_assert(offsetof(GpuInstance, normal_to_world) == 64);
static_assert(offsetof(GpuInstance, first_geometry) == 128);
static_assert(offsetof(GpuInstance, mesh) == 132);
static_assert(offsetof(GpuInstance, pad0) == 136);
static_assert(offsetof(GpuInstance, pad1) == 140);

static_assert(sizeof(GpuMaterial) == 48);
static_assert(offsetof(GpuMaterial, base_color) == 0);
static_assert(offsetof(GpuMaterial, emissive) == 16);
static_assert(offsetof(GpuMaterial, base_color_texture) == 28);
static_assert(offsetof(GpuMaterial, emissive_texture) == 32);
static_assert(offsetof(GpuMaterial, alpha_cutoff) == 36);
static_assert(offsetof(GpuMaterial, transmission) == 40);
static_assert(offsetof(GpuMaterial, pad0) == 44);

static_assert(sizeof(GpuLight) == 64);
static_assert(offsetof(GpuLight, position) == 0);
static_assert(offsetof(GpuLight, type) == 12);
static_assert(offsetof(GpuLight, direction) == 16);
static_assert(offsetof(GpuLight, range) == 28);
static_assert(offsetof(GpuLight, radiance) == 32);
static_assert(offsetof(GpuLight, spot_scale) == 44);
static_assert(offsetof(GpuLight, spot_offset) == 48);
static_assert(offsetof(GpuLight, radius) == 52);
static_assert(offsetof(GpuLight, pad0) == 56);
static_assert(offsetof(GpuLight, pad1) == 60);

static_assert(sizeof(SceneGlobals) == 72);
static_assert(offsetof(SceneGlobals, environment_color) == 0);
static_assert(offsetof(SceneGlobals, environment_has_map) == 12);
static_assert(offsetof(SceneGlobals, environment_intensity) == 16);
static_assert(offsetof(SceneGlobals, environment_rotation) == 20);
static_assert(offsetof(SceneGlobals, light_count) == 24);
static_assert(offsetof(SceneGlobals, flags) == 28);
static_assert(offsetof(SceneGlobals, bounds_min) == 32);
static_assert(offsetof(SceneGlobals, scene_scale) == 44);
static_assert(offsetof(SceneGlobals, bounds_max) == 48);
static_assert(offsetof(SceneGlobals, ray_epsilon) == 60);
static_assert(offsetof(SceneGlobals, emitter_count) == 64);
static_assert(offsetof(SceneGlobals, emitter_total_weight) == 68);

static_assert(sizeof(GpuEmitter) == 80);
static_assert(offsetof(GpuEmitter, p0) == 0);
static_assert(offsetof(GpuEmitter, instance) == 12);
static_assert(offsetof(GpuEmitter, p1) == 16);
static_assert(offsetof(GpuEmitter, geometry) == 28);
static_assert(offsetof(GpuEmitter, p2) == 32);
static_assert(offsetof(GpuEmitter, primitive) == 44);
static_assert(offsetof(GpuEmitter, normal) == 48);
static_assert(offsetof(GpuEmitter, area) == 60);
static_assert(offsetof(GpuEmitter, emission) == 64);
static_assert(offsetof(GpuEmitter, cdf) == 76);
#endif

DDGI_NAMESPACE_END

#endif
