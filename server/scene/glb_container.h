// The binary glTF container (glTF 2.0 spec, "GLB File Format Specification"), checked here in
// full before any parser sees it: every length field of an uploaded file may lie.
#pragma once

#include <cstdint>
#include <span>

#include "core/result.h"

namespace ddgi {

struct GlbChunks {
  std::span<const uint8_t> json;
  std::span<const uint8_t> bin;  // empty when the file has no BIN chunk
};

// True when the bytes start with the GLB magic "glTF".
bool has_glb_magic(std::span<const uint8_t> bytes);

// Checks magic, version 2, total length == bytes.size(), the JSON chunk first, then at most
// one BIN chunk (non-empty), every chunk 4-byte aligned and inside the file. Chunks after
// the BIN chunk are ignored as the spec requires, but their lengths must still be in bounds.
Result<GlbChunks> parse_glb_container(std::span<const uint8_t> bytes);

}  // namespace ddgi
