#include "scene/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "scene/gltf_parse.h"
#include "scene/gltf_values.h"
#include "scene/image_decode.h"

namespace ddgi {
namespace {

std::string material_name(size_t index) {
  return "materials[" + std::to_string(index) + "]";
}

// Texture slots of Scene::textures, one per glTF image that a material colour uses.
class TextureTable {
 public:
  explicit TextureTable(const tinygltf::Model& model) : model_(model) {}

  // The Scene texture for glTF texture info (index, texCoord), or -1 with a warning when the
  // texture cannot be used.
  int slot_for(const tinygltf::TextureInfo& info, const std::string& where,
               std::vector<std::string>* warnings) {
    if (info.index < 0) return -1;
    if (info.texCoord > 1) {
      warnings->push_back(where + ": texCoord " + std::to_string(info.texCoord) +
                          " is not supported (only TEXCOORD_0 and TEXCOORD_1); texture ignored");
      return -1;
    }
    const int image = model_.textures[static_cast<size_t>(info.index)].source;
    if (image < 0) {
      warnings->push_back(where + ": textures[" + std::to_string(info.index) +
                          "] has no PNG/JPEG source; texture ignored");
      return -1;
    }
    const auto [it, added] = slots_.try_emplace(image, static_cast<int>(images_.size()));
    if (added) images_.push_back(image);
    return it->second;
  }

  // Decodes every image handed a slot, in slot order.
  Result<std::vector<Texture>> decode(uint64_t max_total_bytes) const {
    uint64_t total = 0;
    for (int image : images_) {
      const tinygltf::Image& source = model_.images[static_cast<size_t>(image)];
      total += ImageSize{static_cast<uint32_t>(source.width), static_cast<uint32_t>(source.height)}
                   .rgba8_bytes();
    }
    if (total > max_total_bytes) {
      return resource_exhausted("the textures need " + std::to_string(total) +
                                " bytes decoded, more than the limit of " +
                                std::to_string(max_total_bytes));
    }
    std::vector<Texture> textures;
    for (int image : images_) {
      const tinygltf::Image& source = model_.images[static_cast<size_t>(image)];
      const ImageSize size{static_cast<uint32_t>(source.width),
                           static_cast<uint32_t>(source.height)};
      Result<std::vector<uint8_t>> rgba = decode_rgba8(encoded_image(model_, source), size);
      if (!rgba.ok()) return rgba.error().with_context("images[" + std::to_string(image) + "]");
      Texture texture;
      texture.name = !source.name.empty()  ? source.name
                     : !source.uri.empty() ? source.uri
                                           : "images[" + std::to_string(image) + "]";
      texture.width = size.width;
      texture.height = size.height;
      texture.rgba8 = std::move(rgba).value();
      texture.srgb = true;  // only base colour and emission are kept, both sRGB
      textures.push_back(std::move(texture));
    }
    return textures;
  }

 private:
  const tinygltf::Model& model_;
  std::map<int, int> slots_;  // image index -> slot
  std::vector<int> images_;   // slot -> image index
};

float clamp01(double value) {
  return static_cast<float>(std::clamp(value, 0.0, 1.0));
}

Result<double> extension_number(const tinygltf::Material& mat, const char* extension,
                                const char* key, double fallback, size_t index) {
  const std::string where = material_name(index) + ".extensions." + extension;
  DDGI_ASSIGN_OR_RETURN(const std::optional<double> value,
                        optional_number(find_extension(mat.extensions, extension), key, where));
  if (value && *value < 0.0) return invalid_argument(where + "." + key + " must be >= 0");
  return value.value_or(fallback);
}

Result<Material> convert_material(const tinygltf::Model& model, size_t index,
                                  const MaterialOverrides& overrides, TextureTable* textures,
                                  std::vector<std::string>* warnings) {
  const tinygltf::Material& mat = model.materials[index];
  const std::string where = material_name(index);
  Material out;
  out.name = mat.name;
  const auto& pbr = mat.pbrMetallicRoughness;
  // The spec bounds every colour factor to [0, 1]; clamping keeps energy conserving.
  glm::vec4 base_color;
  for (int c = 0; c < 4; ++c) base_color[c] = clamp01(pbr.baseColorFactor[static_cast<size_t>(c)]);
  glm::vec3 emissive_factor;
  for (int c = 0; c < 3; ++c) {
    // Emission above 1 predates KHR_materials_emissive_strength and is common; keep it.
    emissive_factor[c] =
        static_cast<float>(std::max(mat.emissiveFactor[static_cast<size_t>(c)], 0.0));
  }
  DDGI_ASSIGN_OR_RETURN(
      const double strength,
      extension_number(mat, "KHR_materials_emissive_strength", "emissiveStrength", 1.0, index));
  DDGI_ASSIGN_OR_RETURN(
      const double transmission,
      extension_number(mat, "KHR_materials_transmission", "transmissionFactor", 0.0, index));
  out.base_color = base_color;
  out.emissive = emissive_factor * static_cast<float>(strength);
  out.transmission = clamp01(transmission);
  out.double_sided = mat.doubleSided;
  out.alpha_mode = mat.alphaMode == "MASK"    ? AlphaMode::kMask
                   : mat.alphaMode == "BLEND" ? AlphaMode::kBlend
                                              : AlphaMode::kOpaque;
  out.alpha_cutoff = static_cast<float>(mat.alphaCutoff);

  out.base_color_texture = textures->slot_for(
      pbr.baseColorTexture, where + ".pbrMetallicRoughness.baseColorTexture", warnings);
  out.base_color_texcoord = out.base_color_texture >= 0 ? pbr.baseColorTexture.texCoord : 0;
  out.emissive_texture =
      textures->slot_for(mat.emissiveTexture, where + ".emissiveTexture", warnings);
  out.emissive_texcoord = out.emissive_texture >= 0 ? mat.emissiveTexture.texCoord : 0;

  const auto override_it = overrides.find(mat.name);
  if (override_it != overrides.end()) {
    const MaterialOverride& o = override_it->second;
    if (o.base_color) out.base_color = *o.base_color;
    out.emissive = o.emissive.value_or(emissive_factor) *
                   o.emissive_strength.value_or(static_cast<float>(strength));
    if (o.transmission) out.transmission = *o.transmission;
    if (o.double_sided) out.double_sided = *o.double_sided;
  }
  if (!std::isfinite(out.emissive.x) || !std::isfinite(out.emissive.y) ||
      !std::isfinite(out.emissive.z)) {
    return invalid_argument(where + ": emissive factor x strength overflows a float");
  }
  return out;
}

}  // namespace

Status convert_materials(const tinygltf::Model& model, const MaterialOverrides& overrides,
                         const SceneLimits& limits, Scene* scene) {
  TextureTable textures(model);
  scene->materials.clear();
  for (size_t i = 0; i < model.materials.size(); ++i) {
    DDGI_ASSIGN_OR_RETURN(Material material,
                          convert_material(model, i, overrides, &textures, &scene->warnings));
    scene->materials.push_back(std::move(material));
  }
  DDGI_ASSIGN_OR_RETURN(scene->textures, textures.decode(limits.max_total_texture_bytes));
  return ok_status();
}

}  // namespace ddgi
