#include "scene/accessor_reader.h"

#include <cmath>
#include <cstring>

namespace ddgi {
namespace {

std::string accessor_name(int index) {
  return "accessors[" + std::to_string(index) + "]";
}

uint64_t component_bytes(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not glTF 2.0 accessor component types
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    default:
      return "a matrix type";
  }
}

// offset + length <= limit, without overflow.
bool fits(uint64_t offset, uint64_t length, uint64_t limit) {
  return offset <= limit && length <= limit - offset;
}

// The byte range of `count` items of `item_bytes` at `offset` inside bufferView `view_index`.
Result<const uint8_t*> view_range(const tinygltf::Model& model, int view_index, uint64_t offset,
                                  uint64_t count, uint64_t item_bytes, const std::string& what) {
  Result<std::span<const uint8_t>> view = buffer_view_bytes(model, view_index);
  if (!view.ok()) return view.error().with_context(what);
  uint64_t bytes = 0;
  if (__builtin_mul_overflow(count, item_bytes, &bytes) || !fits(offset, bytes, view->size())) {
    return invalid_argument(
        what + ": " + std::to_string(count) + " items of " + std::to_string(item_bytes) +
        " bytes at byteOffset " + std::to_string(offset) + " do not fit in bufferViews[" +
        std::to_string(view_index) + "] (byteLength " + std::to_string(view->size()) + ")");
  }
  return view->data() + offset;
}

template <typename T>
T load(const uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// One component as a float, normalized integers mapped as glTF 2.0 section 3.11 says.
float component_as_float(const uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = load<int8_t>(p);
      return normalized ? std::fmax(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = load<uint8_t>(p);
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float v = load<int16_t>(p);
      return normalized ? std::fmax(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float v = load<uint16_t>(p);
      return normalized ? v / 65535.0f : v;
    }
    default:
      return 0.0f;  // excluded by the callers' checks
  }
}

uint32_t component_as_uint(const uint8_t* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return load<uint8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return load<uint16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return load<uint32_t>(p);
    default:
      return 0;  // excluded by the callers' checks
  }
}

bool is_index_type(int component_type) {
  return component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
         component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

struct SparseLayout {
  uint64_t count = 0;
  int index_type = 0;
  const uint8_t* indices = nullptr;
  const uint8_t* values = nullptr;
};

Result<SparseLayout> describe_sparse(const tinygltf::Model& model, int index,
                                     const AccessorLayout& layout) {
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string what = accessor_name(index) + ".sparse";
  const auto& sparse = accessor.sparse;
  if (sparse.count < 1 || static_cast<uint64_t>(sparse.count) > layout.count) {
    return invalid_argument(what + ".count " + std::to_string(sparse.count) + " is outside [1, " +
                            std::to_string(layout.count) + "]");
  }
  if (!is_index_type(sparse.indices.componentType)) {
    return invalid_argument(what + ".indices.componentType " +
                            std::to_string(sparse.indices.componentType) +
                            " must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
    return invalid_argument(what + ": negative byteOffset");
  }
  SparseLayout result;
  result.count = static_cast<uint64_t>(sparse.count);
  result.index_type = sparse.indices.componentType;
  DDGI_ASSIGN_OR_RETURN(
      result.indices,
      view_range(model, sparse.indices.bufferView, static_cast<uint64_t>(sparse.indices.byteOffset),
                 result.count, component_bytes(result.index_type), what + ".indices"));
  DDGI_ASSIGN_OR_RETURN(
      result.values,
      view_range(model, sparse.values.bufferView, static_cast<uint64_t>(sparse.values.byteOffset),
                 result.count, layout.element_bytes, what + ".values"));
  return result;
}

// Calls write(element, source) for every sparse substitution, after checking its index.
template <typename Write>
Status for_each_sparse(const tinygltf::Model& model, int index, const AccessorLayout& layout,
                       Write write) {
  if (!model.accessors[static_cast<size_t>(index)].sparse.isSparse) return ok_status();
  DDGI_ASSIGN_OR_RETURN(const SparseLayout sparse, describe_sparse(model, index, layout));
  const uint64_t index_bytes = component_bytes(sparse.index_type);
  for (uint64_t s = 0; s < sparse.count; ++s) {
    const uint32_t element = component_as_uint(sparse.indices + s * index_bytes, sparse.index_type);
    if (element >= layout.count) {
      return invalid_argument(accessor_name(index) + ".sparse.indices[" + std::to_string(s) +
                              "] = " + std::to_string(element) + " is out of range (count " +
                              std::to_string(layout.count) + ")");
    }
    write(element, sparse.values + s * layout.element_bytes);
  }
  return ok_status();
}

}  // namespace

Result<std::span<const uint8_t>> buffer_view_bytes(const tinygltf::Model& model, int index) {
  const std::string what = "bufferViews[" + std::to_string(index) + "]";
  if (index < 0 || static_cast<size_t>(index) >= model.bufferViews.size()) {
    return invalid_argument(what + " does not exist (the file has " +
                            std::to_string(model.bufferViews.size()) + ")");
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(index)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size()) {
    return invalid_argument(what + ".buffer " + std::to_string(view.buffer) +
                            " does not exist (the file has " +
                            std::to_string(model.buffers.size()) + ")");
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
  if (!fits(view.byteOffset, view.byteLength, data.size())) {
    return invalid_argument(what + " (byteOffset " + std::to_string(view.byteOffset) +
                            ", byteLength " + std::to_string(view.byteLength) +
                            ") runs past the end of buffers[" + std::to_string(view.buffer) +
                            "] (" + std::to_string(data.size()) + " bytes)");
  }
  return std::span<const uint8_t>(data.data() + view.byteOffset, view.byteLength);
}

Result<AccessorLayout> describe_accessor(const tinygltf::Model& model, int index) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    return invalid_argument(accessor_name(index) + " does not exist (the file has " +
                            std::to_string(model.accessors.size()) + ")");
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string what = accessor_name(index);
  AccessorLayout layout;
  layout.component_bytes = component_bytes(accessor.componentType);
  if (layout.component_bytes == 0) {
    return invalid_argument(what + ".componentType " + std::to_string(accessor.componentType) +
                            " is not a glTF 2.0 accessor component type");
  }
  layout.components = component_count(accessor.type);
  if (layout.components == 0) return invalid_argument(what + ".type is not valid");
  layout.count = accessor.count;
  if (layout.count == 0) return invalid_argument(what + ".count must be at least 1");
  layout.element_bytes = layout.component_bytes * static_cast<uint64_t>(layout.components);
  layout.stride = layout.element_bytes;
  if (accessor.bufferView != -1) {
    Result<std::span<const uint8_t>> view = buffer_view_bytes(model, accessor.bufferView);
    if (!view.ok()) return view.error().with_context(what);
    const tinygltf::BufferView& info = model.bufferViews[static_cast<size_t>(accessor.bufferView)];
    if (info.byteStride != 0) {
      layout.stride = info.byteStride;
      if (layout.stride < layout.element_bytes) {
        return invalid_argument(what + ": bufferViews[" + std::to_string(accessor.bufferView) +
                                "].byteStride " + std::to_string(info.byteStride) +
                                " is smaller than one element (" +
                                std::to_string(layout.element_bytes) + " bytes)");
      }
    }
    // The last element ends at byteOffset + stride * (count - 1) + element size.
    uint64_t extent = 0;
    if (__builtin_mul_overflow(layout.count - 1, layout.stride, &extent) ||
        __builtin_add_overflow(extent, layout.element_bytes, &extent) ||
        !fits(accessor.byteOffset, extent, view->size())) {
      return invalid_argument(what + ": " + std::to_string(layout.count) + " elements of " +
                              std::to_string(layout.element_bytes) + " bytes (stride " +
                              std::to_string(layout.stride) + ", byteOffset " +
                              std::to_string(accessor.byteOffset) + ") do not fit in bufferViews[" +
                              std::to_string(accessor.bufferView) + "] (byteLength " +
                              std::to_string(view->size()) + ")");
    }
    layout.first = view->data() + accessor.byteOffset;
  }
  if (accessor.sparse.isSparse) DDGI_TRY(describe_sparse(model, index, layout));
  return layout;
}

Result<std::vector<float>> read_float_accessor(const tinygltf::Model& model, int index,
                                               int expected_type, bool require_normalized_ints,
                                               uint64_t max_count, const std::string& what) {
  DDGI_ASSIGN_OR_RETURN(const AccessorLayout layout, describe_accessor(model, index));
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string where = what + " (" + accessor_name(index) + ")";
  if (accessor.type != expected_type) {
    return invalid_argument(where + " must be " + type_name(expected_type));
  }
  const int ctype = accessor.componentType;
  if (ctype == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    return invalid_argument(where + ": componentType UNSIGNED_INT is not allowed for attributes");
  }
  if (ctype != TINYGLTF_COMPONENT_TYPE_FLOAT && require_normalized_ints && !accessor.normalized) {
    return invalid_argument(where + ": integer components must be normalized");
  }
  if (layout.count > max_count) {
    return resource_exhausted(where + ": count " + std::to_string(layout.count) +
                              " exceeds the vertex limit (" + std::to_string(max_count) + " left)");
  }
  const size_t comps = static_cast<size_t>(layout.components);
  std::vector<float> values(static_cast<size_t>(layout.count) * comps, 0.0f);
  auto read_element = [&](uint64_t element, const uint8_t* source) {
    for (size_t c = 0; c < comps; ++c) {
      values[element * comps + c] =
          component_as_float(source + c * layout.component_bytes, ctype, accessor.normalized);
    }
  };
  if (layout.first != nullptr) {
    for (uint64_t i = 0; i < layout.count; ++i) read_element(i, layout.first + i * layout.stride);
  }
  DDGI_TRY(for_each_sparse(model, index, layout, read_element));
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      return invalid_argument(where + ": element " + std::to_string(i / comps) + " component " +
                              std::to_string(i % comps) + " is " +
                              (std::isnan(values[i]) ? "NaN" : "infinite"));
    }
  }
  return values;
}

Result<std::vector<uint32_t>> read_index_accessor(const tinygltf::Model& model, int index,
                                                  uint64_t max_count, const std::string& what) {
  DDGI_ASSIGN_OR_RETURN(const AccessorLayout layout, describe_accessor(model, index));
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string where = what + " (" + accessor_name(index) + ")";
  if (accessor.type != TINYGLTF_TYPE_SCALAR) return invalid_argument(where + " must be SCALAR");
  if (!is_index_type(accessor.componentType)) {
    return invalid_argument(where + ": componentType " + std::to_string(accessor.componentType) +
                            " must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  }
  if (layout.count > max_count) {
    return resource_exhausted(where + ": count " + std::to_string(layout.count) +
                              " exceeds the index limit (" + std::to_string(max_count) + ")");
  }
  std::vector<uint32_t> indices(static_cast<size_t>(layout.count), 0);
  auto read_element = [&](uint64_t element, const uint8_t* source) {
    indices[element] = component_as_uint(source, accessor.componentType);
  };
  if (layout.first != nullptr) {
    for (uint64_t i = 0; i < layout.count; ++i) read_element(i, layout.first + i * layout.stride);
  }
  DDGI_TRY(for_each_sparse(model, index, layout, read_element));
  return indices;
}

}  // namespace ddgi
