// FNV-1a over bytes, 64 bits: a hash that stays the same between runs, builds and machines
// (which std::hash does not promise), for cache keys and the names of files kept on disk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ddgi {

inline constexpr uint64_t kFnv1aSeed = 14695981039346656037ull;

inline uint64_t fnv1a(uint64_t hash, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
  return hash;
}

inline uint64_t fnv1a(std::string_view text) {
  return fnv1a(kFnv1aSeed, text.data(), text.size());
}

}  // namespace ddgi
