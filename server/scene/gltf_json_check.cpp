// The glTF members checked here follow the glTF 2.0 schema for everything tinygltf reads
// (core objects, KHR_lights_punctual, KHR_materials_emissive_strength and _transmission);
// `extras` and unknown extensions are never looked into.
#include "scene/gltf_json_check.h"

#include <cstdint>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

namespace ddgi {
namespace {

using json = nlohmann::json;

constexpr size_t kMaxShownBytes = 40;

// The value as JSON text, cut to a length fit for a message (client text stays short).
std::string show(const json& value) {
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > kMaxShownBytes) text = text.substr(0, kMaxShownBytes - 3) + "...";
  return text;
}

std::string item(const std::string& array, size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

std::string member_path(const std::string& where, const char* key) {
  return where.empty() ? std::string(key) : where + "." + key;
}

const json* find(const json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

bool non_negative_integer(const json& value) {
  return value.is_number_unsigned() || (value.is_number_integer() && value.get<int64_t>() >= 0);
}

Status wrong(const std::string& path, const char* expected, const json& value) {
  return invalid_argument(path + ": expected " + expected + ", got " + show(value));
}

class Checker {
 public:
  explicit Checker(const json& doc) : doc_(doc) {}

  Status run() {
    if (!doc_.is_object()) return wrong("the document", "a JSON object", doc_);
    static const char* const kArrays[] = {
        "accessors", "animations", "buffers",  "bufferViews", "cameras", "images",  "materials",
        "meshes",    "nodes",      "samplers", "scenes",      "skins",   "textures"};
    for (const char* name : kArrays) DDGI_TRY(objects(doc_, name, ""));
    DDGI_TRY(strings(doc_, "extensionsUsed", ""));
    DDGI_TRY(strings(doc_, "extensionsRequired", ""));
    DDGI_TRY(check_lights());
    DDGI_TRY(index(doc_, "scene", "", "scenes"));
    DDGI_TRY(each("scenes", &Checker::scene));
    DDGI_TRY(each("nodes", &Checker::node));
    DDGI_TRY(each("meshes", &Checker::mesh));
    DDGI_TRY(each("materials", &Checker::material));
    DDGI_TRY(each("textures", &Checker::texture));
    DDGI_TRY(each("images", &Checker::image));
    DDGI_TRY(each("samplers", &Checker::sampler));
    DDGI_TRY(each("accessors", &Checker::accessor));
    DDGI_TRY(each("bufferViews", &Checker::buffer_view));
    DDGI_TRY(each("buffers", &Checker::buffer));
    DDGI_TRY(each("cameras", &Checker::camera));
    DDGI_TRY(each("skins", &Checker::skin));
    return each("animations", &Checker::animation);
  }

 private:
  // Elements of a top-level array; 0 when it is absent (its type was checked first).
  size_t count(const char* array) const {
    const json* value = find(doc_, array);
    return value != nullptr && value->is_array() ? value->size() : 0;
  }

  using Check = Status (Checker::*)(const json&, const std::string&) const;

  Status each(const char* array, Check check) const {
    const json* list = find(doc_, array);
    if (list == nullptr) return ok_status();
    for (size_t i = 0; i < list->size(); ++i) DDGI_TRY((this->*check)((*list)[i], item(array, i)));
    return ok_status();
  }

  // `key`, when present, is an array whose elements are all objects.
  static Status objects(const json& object, const char* key, const std::string& where) {
    const json* list = find(object, key);
    if (list == nullptr) return ok_status();
    const std::string path = member_path(where, key);
    if (!list->is_array()) return wrong(path, "an array of objects", *list);
    for (size_t i = 0; i < list->size(); ++i) {
      if (!(*list)[i].is_object()) return wrong(item(path, i), "an object", (*list)[i]);
    }
    return ok_status();
  }

  // `key`, when present, is an object; *out points at it (nullptr when absent).
  static Status object(const json& parent, const char* key, const std::string& where,
                       const json** out) {
    *out = find(parent, key);
    if (*out != nullptr && !(*out)->is_object()) {
      return wrong(member_path(where, key), "an object", **out);
    }
    return ok_status();
  }

  static Status index_value(const json& value, const std::string& path, const char* target,
                            size_t size) {
    if (!non_negative_integer(value)) return wrong(path, "a non-negative integer index", value);
    const uint64_t index = value.get<uint64_t>();
    if (index >= size) {
      return invalid_argument(path + " = " + std::to_string(index) +
                              " does not exist (the file has " + std::to_string(size) + " " +
                              target + ")");
    }
    return ok_status();
  }

  // An index into the top-level array `target`.
  Status index(const json& object, const char* key, const std::string& where,
               const char* target) const {
    const json* value = find(object, key);
    if (value == nullptr) return ok_status();
    return index_value(*value, member_path(where, key), target, count(target));
  }

  Status indices(const json& object, const char* key, const std::string& where,
                 const char* target) const {
    const json* list = find(object, key);
    if (list == nullptr) return ok_status();
    const std::string path = member_path(where, key);
    if (!list->is_array()) return wrong(path, "an array of indices", *list);
    for (size_t i = 0; i < list->size(); ++i) {
      DDGI_TRY(index_value((*list)[i], item(path, i), target, count(target)));
    }
    return ok_status();
  }

  // An object whose every member is an index into `target` (attributes, morph targets).
  Status index_map(const json& map, const std::string& path, const char* target) const {
    if (!map.is_object()) return wrong(path, "an object of accessor indices", map);
    for (const auto& [key, value] : map.items()) {
      DDGI_TRY(index_value(value, path + "." + key, target, count(target)));
    }
    return ok_status();
  }

  static Status integer(const json& object, const char* key, const std::string& where, int64_t min,
                        int64_t max) {
    const json* value = find(object, key);
    if (value == nullptr) return ok_status();
    const bool in_range = value->is_number_unsigned()
                              ? value->get<uint64_t>() <= static_cast<uint64_t>(max)
                              : value->is_number_integer() && value->get<int64_t>() >= min &&
                                    value->get<int64_t>() <= max;
    if (in_range) return ok_status();
    const std::string path = member_path(where, key);
    if (min == 0 && (max == INT32_MAX || max == UINT32_MAX)) {
      return wrong(path, "a non-negative integer", *value);
    }
    const std::string range =
        "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    return wrong(path, range.c_str(), *value);
  }

  // A member that, when present, must be one JSON type (`expected` names it in the message).
  static Status typed(const json& object, const char* key, const std::string& where,
                      bool (json::*is)() const noexcept, const char* expected) {
    const json* value = find(object, key);
    if (value != nullptr && !(value->*is)()) {
      return wrong(member_path(where, key), expected, *value);
    }
    return ok_status();
  }

  // A member that, when present, must be an array of one JSON type.
  static Status typed_list(const json& object, const char* key, const std::string& where,
                           bool (json::*is)() const noexcept, const char* expected,
                           const char* expected_list) {
    const json* list = find(object, key);
    if (list == nullptr) return ok_status();
    const std::string path = member_path(where, key);
    if (!list->is_array()) return wrong(path, expected_list, *list);
    for (size_t i = 0; i < list->size(); ++i) {
      if (!((*list)[i].*is)()) return wrong(item(path, i), expected, (*list)[i]);
    }
    return ok_status();
  }

  static Status number(const json& object, const char* key, const std::string& where) {
    return typed(object, key, where, &json::is_number, "a number");
  }
  static Status numbers(const json& object, const char* key, const std::string& where) {
    return typed_list(object, key, where, &json::is_number, "a number", "an array of numbers");
  }
  static Status string(const json& object, const char* key, const std::string& where) {
    return typed(object, key, where, &json::is_string, "a string");
  }
  static Status strings(const json& object, const char* key, const std::string& where) {
    return typed_list(object, key, where, &json::is_string, "a string", "an array of strings");
  }
  static Status boolean(const json& object, const char* key, const std::string& where) {
    return typed(object, key, where, &json::is_boolean, "true or false");
  }

  static Status name(const json& object, const std::string& where) {
    return string(object, "name", where);
  }

  // The object extensions.NAME of `parent`, nullptr when absent.
  static Status extension(const json& parent, const char* extension_name, const std::string& where,
                          const json** out) {
    *out = nullptr;
    const json* extensions = nullptr;
    DDGI_TRY(object(parent, "extensions", where, &extensions));
    if (extensions == nullptr) return ok_status();
    return object(*extensions, extension_name, member_path(where, "extensions"), out);
  }

  Status check_lights() {
    const json* punctual = nullptr;
    DDGI_TRY(extension(doc_, "KHR_lights_punctual", "", &punctual));
    if (punctual == nullptr) return ok_status();
    const std::string where = "extensions.KHR_lights_punctual";
    DDGI_TRY(objects(*punctual, "lights", where));
    const json* lights = find(*punctual, "lights");
    if (lights == nullptr) return ok_status();
    light_count_ = lights->size();
    for (size_t i = 0; i < lights->size(); ++i) {
      const json& light = (*lights)[i];
      const std::string path = item(where + ".lights", i);
      DDGI_TRY(name(light, path));
      DDGI_TRY(string(light, "type", path));
      DDGI_TRY(numbers(light, "color", path));
      DDGI_TRY(number(light, "intensity", path));
      DDGI_TRY(number(light, "range", path));
      const json* spot = nullptr;
      DDGI_TRY(object(light, "spot", path, &spot));
      if (spot != nullptr) {
        DDGI_TRY(number(*spot, "innerConeAngle", path + ".spot"));
        DDGI_TRY(number(*spot, "outerConeAngle", path + ".spot"));
      }
    }
    return ok_status();
  }

  Status scene(const json& s, const std::string& where) const {
    DDGI_TRY(name(s, where));
    return indices(s, "nodes", where, "nodes");
  }

  Status texture(const json& t, const std::string& where) const {
    DDGI_TRY(name(t, where));
    DDGI_TRY(index(t, "sampler", where, "samplers"));
    return index(t, "source", where, "images");
  }

  Status image(const json& i, const std::string& where) const {
    DDGI_TRY(name(i, where));
    DDGI_TRY(string(i, "uri", where));
    DDGI_TRY(string(i, "mimeType", where));
    return index(i, "bufferView", where, "bufferViews");
  }

  Status sampler(const json& s, const std::string& where) const {
    DDGI_TRY(name(s, where));
    for (const char* key : {"magFilter", "minFilter", "wrapS", "wrapT"}) {
      DDGI_TRY(integer(s, key, where, 0, INT32_MAX));
    }
    return ok_status();
  }

  Status buffer_view(const json& view, const std::string& where) const {
    DDGI_TRY(name(view, where));
    DDGI_TRY(index(view, "buffer", where, "buffers"));
    for (const char* key : {"byteOffset", "byteLength", "byteStride", "target"}) {
      DDGI_TRY(integer(view, key, where, 0, UINT32_MAX));
    }
    return ok_status();
  }

  Status buffer(const json& b, const std::string& where) const {
    DDGI_TRY(name(b, where));
    DDGI_TRY(string(b, "uri", where));
    return integer(b, "byteLength", where, 0, UINT32_MAX);
  }

  Status skin(const json& s, const std::string& where) const {
    DDGI_TRY(name(s, where));
    DDGI_TRY(index(s, "inverseBindMatrices", where, "accessors"));
    DDGI_TRY(index(s, "skeleton", where, "nodes"));
    return indices(s, "joints", where, "nodes");
  }

  Status node(const json& n, const std::string& where) const {
    DDGI_TRY(name(n, where));
    DDGI_TRY(index(n, "camera", where, "cameras"));
    DDGI_TRY(index(n, "skin", where, "skins"));
    DDGI_TRY(index(n, "mesh", where, "meshes"));
    DDGI_TRY(indices(n, "children", where, "nodes"));
    for (const char* key : {"matrix", "rotation", "scale", "translation", "weights"}) {
      DDGI_TRY(numbers(n, key, where));
    }
    const json* light = nullptr;
    DDGI_TRY(extension(n, "KHR_lights_punctual", where, &light));
    if (light != nullptr) {
      const json* value = find(*light, "light");
      const std::string path = where + ".extensions.KHR_lights_punctual.light";
      if (value == nullptr) return invalid_argument(path + " is missing");
      DDGI_TRY(index_value(*value, path, "KHR_lights_punctual lights", light_count_));
    }
    return ok_status();
  }

  Status mesh(const json& m, const std::string& where) const {
    DDGI_TRY(name(m, where));
    DDGI_TRY(numbers(m, "weights", where));
    DDGI_TRY(objects(m, "primitives", where));
    const json* primitives = find(m, "primitives");
    if (primitives == nullptr) return ok_status();
    for (size_t p = 0; p < primitives->size(); ++p) {
      const json& prim = (*primitives)[p];
      const std::string path = item(where + ".primitives", p);
      const json* attributes = find(prim, "attributes");
      if (attributes != nullptr) {
        DDGI_TRY(index_map(*attributes, path + ".attributes", "accessors"));
      }
      DDGI_TRY(index(prim, "indices", path, "accessors"));
      DDGI_TRY(index(prim, "material", path, "materials"));
      DDGI_TRY(integer(prim, "mode", path, 0, 6));
      DDGI_TRY(objects(prim, "targets", path));
      const json* targets = find(prim, "targets");
      for (size_t t = 0; targets != nullptr && t < targets->size(); ++t) {
        DDGI_TRY(index_map((*targets)[t], item(path + ".targets", t), "accessors"));
      }
    }
    return ok_status();
  }

  // A textureInfo (and its normal/occlusion variants): which texture, which UV set.
  Status texture_info(const json& parent, const char* key, const std::string& where,
                      const char* factor = nullptr) const {
    const json* info = nullptr;
    DDGI_TRY(object(parent, key, where, &info));
    if (info == nullptr) return ok_status();
    const std::string path = member_path(where, key);
    DDGI_TRY(index(*info, "index", path, "textures"));
    DDGI_TRY(integer(*info, "texCoord", path, 0, INT32_MAX));
    if (factor != nullptr) DDGI_TRY(number(*info, factor, path));
    return ok_status();
  }

  Status material(const json& m, const std::string& where) const {
    DDGI_TRY(name(m, where));
    const json* pbr = nullptr;
    DDGI_TRY(object(m, "pbrMetallicRoughness", where, &pbr));
    if (pbr != nullptr) {
      const std::string path = where + ".pbrMetallicRoughness";
      DDGI_TRY(numbers(*pbr, "baseColorFactor", path));
      DDGI_TRY(number(*pbr, "metallicFactor", path));
      DDGI_TRY(number(*pbr, "roughnessFactor", path));
      DDGI_TRY(texture_info(*pbr, "baseColorTexture", path));
      DDGI_TRY(texture_info(*pbr, "metallicRoughnessTexture", path));
    }
    DDGI_TRY(texture_info(m, "normalTexture", where, "scale"));
    DDGI_TRY(texture_info(m, "occlusionTexture", where, "strength"));
    DDGI_TRY(texture_info(m, "emissiveTexture", where));
    DDGI_TRY(numbers(m, "emissiveFactor", where));
    DDGI_TRY(string(m, "alphaMode", where));
    DDGI_TRY(number(m, "alphaCutoff", where));
    DDGI_TRY(boolean(m, "doubleSided", where));
    const std::string extensions = where + ".extensions";
    const json* strength = nullptr;
    DDGI_TRY(extension(m, "KHR_materials_emissive_strength", where, &strength));
    if (strength != nullptr) {
      DDGI_TRY(
          number(*strength, "emissiveStrength", extensions + ".KHR_materials_emissive_strength"));
    }
    const json* transmission = nullptr;
    DDGI_TRY(extension(m, "KHR_materials_transmission", where, &transmission));
    if (transmission != nullptr) {
      const std::string path = extensions + ".KHR_materials_transmission";
      DDGI_TRY(number(*transmission, "transmissionFactor", path));
      DDGI_TRY(texture_info(*transmission, "transmissionTexture", path));
    }
    return ok_status();
  }

  Status accessor(const json& a, const std::string& where) const {
    DDGI_TRY(name(a, where));
    DDGI_TRY(index(a, "bufferView", where, "bufferViews"));
    DDGI_TRY(integer(a, "byteOffset", where, 0, UINT32_MAX));
    DDGI_TRY(integer(a, "componentType", where, 0, INT32_MAX));
    DDGI_TRY(boolean(a, "normalized", where));
    DDGI_TRY(integer(a, "count", where, 0, UINT32_MAX));
    DDGI_TRY(string(a, "type", where));
    DDGI_TRY(numbers(a, "min", where));
    DDGI_TRY(numbers(a, "max", where));
    const json* sparse = nullptr;
    DDGI_TRY(object(a, "sparse", where, &sparse));
    if (sparse == nullptr) return ok_status();
    const std::string path = where + ".sparse";
    DDGI_TRY(integer(*sparse, "count", path, 0, UINT32_MAX));
    for (const char* part : {"indices", "values"}) {
      const json* section = nullptr;
      DDGI_TRY(object(*sparse, part, path, &section));
      if (section == nullptr) continue;
      const std::string section_path = member_path(path, part);
      DDGI_TRY(index(*section, "bufferView", section_path, "bufferViews"));
      DDGI_TRY(integer(*section, "byteOffset", section_path, 0, UINT32_MAX));
      DDGI_TRY(integer(*section, "componentType", section_path, 0, INT32_MAX));
    }
    return ok_status();
  }

  Status camera(const json& c, const std::string& where) const {
    DDGI_TRY(name(c, where));
    DDGI_TRY(string(c, "type", where));
    const json* perspective = nullptr;
    DDGI_TRY(object(c, "perspective", where, &perspective));
    if (perspective != nullptr) {
      for (const char* key : {"aspectRatio", "yfov", "zfar", "znear"}) {
        DDGI_TRY(number(*perspective, key, where + ".perspective"));
      }
    }
    const json* orthographic = nullptr;
    DDGI_TRY(object(c, "orthographic", where, &orthographic));
    if (orthographic != nullptr) {
      for (const char* key : {"xmag", "ymag", "zfar", "znear"}) {
        DDGI_TRY(number(*orthographic, key, where + ".orthographic"));
      }
    }
    return ok_status();
  }

  Status animation(const json& a, const std::string& where) const {
    DDGI_TRY(name(a, where));
    DDGI_TRY(objects(a, "samplers", where));
    DDGI_TRY(objects(a, "channels", where));
    const json* samplers = find(a, "samplers");
    const size_t sampler_count = samplers != nullptr ? samplers->size() : 0;
    for (size_t s = 0; s < sampler_count; ++s) {
      const std::string path = item(where + ".samplers", s);
      DDGI_TRY(index((*samplers)[s], "input", path, "accessors"));
      DDGI_TRY(index((*samplers)[s], "output", path, "accessors"));
      DDGI_TRY(string((*samplers)[s], "interpolation", path));
    }
    const json* channels = find(a, "channels");
    for (size_t c = 0; channels != nullptr && c < channels->size(); ++c) {
      const json& channel = (*channels)[c];
      const std::string path = item(where + ".channels", c);
      const json* sampler = find(channel, "sampler");
      if (sampler != nullptr) {
        DDGI_TRY(
            index_value(*sampler, path + ".sampler", "samplers in this animation", sampler_count));
      }
      const json* target = nullptr;
      DDGI_TRY(object(channel, "target", path, &target));
      if (target != nullptr) {
        DDGI_TRY(index(*target, "node", path + ".target", "nodes"));
        DDGI_TRY(string(*target, "path", path + ".target"));
      }
    }
    return ok_status();
  }

  const json& doc_;
  size_t light_count_ = 0;
};

}  // namespace

Status check_gltf_json(const nlohmann::json& doc) {
  return Checker(doc).run();
}

}  // namespace ddgi
