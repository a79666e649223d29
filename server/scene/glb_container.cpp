#include "scene/glb_container.h"

#include <string>

namespace ddgi {
namespace {

constexpr uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr uint64_t kHeaderBytes = 12;
constexpr uint64_t kChunkHeaderBytes = 8;

// GLB is little-endian whatever the host.
uint32_t read_u32(std::span<const uint8_t> bytes, uint64_t offset) {
  return static_cast<uint32_t>(bytes[offset]) | static_cast<uint32_t>(bytes[offset + 1]) << 8 |
         static_cast<uint32_t>(bytes[offset + 2]) << 16 |
         static_cast<uint32_t>(bytes[offset + 3]) << 24;
}

std::string hex(uint32_t value) {
  static const char kDigits[] = "0123456789abcdef";
  std::string text = "0x";
  for (int shift = 28; shift >= 0; shift -= 4) text += kDigits[(value >> shift) & 0xF];
  return text;
}

struct Chunk {
  uint32_t type = 0;
  uint64_t data_offset = 0;
  uint64_t length = 0;
};

// The chunk starting at `offset`, checked to lie inside the file.
Result<Chunk> read_chunk(std::span<const uint8_t> bytes, uint64_t offset, int index) {
  const std::string where =
      "GLB chunk " + std::to_string(index) + " at byte " + std::to_string(offset);
  if (offset + kChunkHeaderBytes > bytes.size()) {
    return invalid_argument(where + ": truncated chunk header (" +
                            std::to_string(bytes.size() - offset) + " bytes left, need 8)");
  }
  Chunk chunk;
  chunk.length = read_u32(bytes, offset);
  chunk.type = read_u32(bytes, offset + 4);
  chunk.data_offset = offset + kChunkHeaderBytes;
  if (chunk.length % 4 != 0) {
    return invalid_argument(where + ": chunkLength " + std::to_string(chunk.length) +
                            " is not a multiple of 4");
  }
  if (chunk.data_offset + chunk.length > bytes.size()) {
    return invalid_argument(where + ": chunkLength " + std::to_string(chunk.length) +
                            " runs past the end of the file (" + std::to_string(bytes.size()) +
                            " bytes)");
  }
  return chunk;
}

}  // namespace

bool has_glb_magic(std::span<const uint8_t> bytes) {
  return bytes.size() >= 4 && read_u32(bytes, 0) == kMagic;
}

Result<GlbChunks> parse_glb_container(std::span<const uint8_t> bytes) {
  if (bytes.size() < kHeaderBytes) {
    return invalid_argument("GLB header truncated: " + std::to_string(bytes.size()) +
                            " bytes, need 12");
  }
  if (!has_glb_magic(bytes)) return invalid_argument("not a GLB file: the magic is not 'glTF'");
  const uint32_t version = read_u32(bytes, 4);
  if (version != 2) {
    return invalid_argument("GLB version " + std::to_string(version) +
                            " is not supported (need 2)");
  }
  const uint32_t length = read_u32(bytes, 8);
  if (length != bytes.size()) {
    return invalid_argument("GLB header length " + std::to_string(length) +
                            " does not match the file size " + std::to_string(bytes.size()));
  }

  DDGI_ASSIGN_OR_RETURN(const Chunk json, read_chunk(bytes, kHeaderBytes, 0));
  if (json.type != kChunkJson) {
    return invalid_argument("GLB chunk 0 has type " + hex(json.type) +
                            "; the first chunk must be JSON (0x4e4f534a)");
  }
  if (json.length == 0) return invalid_argument("GLB JSON chunk is empty");

  GlbChunks chunks;
  chunks.json = bytes.subspan(json.data_offset, json.length);
  uint64_t offset = json.data_offset + json.length;
  for (int index = 1; offset < bytes.size(); ++index) {
    DDGI_ASSIGN_OR_RETURN(const Chunk chunk, read_chunk(bytes, offset, index));
    if (chunk.type == kChunkJson) {
      return invalid_argument("GLB chunk " + std::to_string(index) + " is a second JSON chunk");
    }
    if (chunk.type == kChunkBin) {
      if (index != 1) {
        return invalid_argument("GLB chunk " + std::to_string(index) +
                                " is a BIN chunk; only chunk 1 may be BIN");
      }
      if (chunk.length == 0) {
        return invalid_argument("GLB BIN chunk is empty (omit it instead)");
      }
      chunks.bin = bytes.subspan(chunk.data_offset, chunk.length);
    } else if (index == 1) {
      // The parser underneath only understands BIN as chunk 1; extensions' chunks go after it.
      return invalid_argument("GLB chunk 1 has type " + hex(chunk.type) +
                              "; the second chunk must be BIN (0x004e4942)");
    }
    offset = chunk.data_offset + chunk.length;
  }
  return chunks;
}

}  // namespace ddgi
