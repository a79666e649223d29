#include "scene/gltf_values.h"

#include <cmath>

#include "scene/finite.h"

namespace ddgi {
namespace {

const tinygltf::Value* member(const tinygltf::Value* object, const std::string& key) {
  if (object == nullptr || !object->IsObject() || !object->Has(key)) return nullptr;
  return &object->Get(key);
}

}  // namespace

const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& extensions,
                                      const std::string& name) {
  const auto it = extensions.find(name);
  if (it == extensions.end() || !it->second.IsObject()) return nullptr;
  return &it->second;
}

Result<std::optional<double>> optional_number(const tinygltf::Value* object, const std::string& key,
                                              const std::string& where) {
  const tinygltf::Value* value = member(object, key);
  if (value == nullptr) return std::optional<double>();
  if (!value->IsNumber() || !finite_as_float(value->GetNumberAsDouble())) {
    return invalid_argument(where + "." + key + " must be a finite number");
  }
  return std::optional<double>(value->GetNumberAsDouble());
}

Result<std::optional<int>> optional_int(const tinygltf::Value* object, const std::string& key,
                                        const std::string& where) {
  const tinygltf::Value* value = member(object, key);
  if (value == nullptr) return std::optional<int>();
  if (!value->IsInt()) return invalid_argument(where + "." + key + " must be an integer");
  return std::optional<int>(value->GetNumberAsInt());
}

}  // namespace ddgi
