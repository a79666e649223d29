// Reads glTF accessors (spec section 3.6) with every range checked: strides, byte offsets,
// sparse substitution, normalized integers. Nothing in an accessor (min/max included) is
// trusted.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "core/result.h"

namespace ddgi {

// The bytes of bufferView `index`, checked to lie inside its buffer's data.
Result<std::span<const uint8_t>> buffer_view_bytes(const tinygltf::Model& model, int index);

// Where an accessor's elements lie; computing it checks that they fit in the buffer view.
struct AccessorLayout {
  uint64_t count = 0;
  int components = 0;  // 1 (SCALAR) .. 16 (MAT4)
  uint64_t component_bytes = 0;
  uint64_t element_bytes = 0;
  uint64_t stride = 0;
  const uint8_t* first = nullptr;  // element 0; nullptr when there is no bufferView (zeros)
};

// Checks accessor `index` (ranges of its bufferView and of its sparse views) without reading
// any element.
Result<AccessorLayout> describe_accessor(const tinygltf::Model& model, int index);

// An attribute as floats (count * components values), integers converted as the spec says for
// normalized/unnormalized values. Fails on other accessor types, on component types not
// allowed for attributes, when count exceeds max_count, or on NaN/Inf. `what` names the
// attribute in messages (e.g. "meshes[0].primitives[1].attributes.POSITION").
Result<std::vector<float>> read_float_accessor(const tinygltf::Model& model, int index,
                                               int expected_type, bool require_normalized_ints,
                                               uint64_t max_count, const std::string& what);

// Triangle-corner indices: SCALAR of UNSIGNED_BYTE/SHORT/INT.
Result<std::vector<uint32_t>> read_index_accessor(const tinygltf::Model& model, int index,
                                                  uint64_t max_count, const std::string& what);

}  // namespace ddgi
