// File access for scene loading. A glTF may only read files inside its own folder: its URIs
// come from untrusted input, so every one is resolved here and refused when it would leave.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi {

// The whole file, or an error when it is missing, unreadable or larger than max_bytes.
Result<std::vector<uint8_t>> read_file(const std::filesystem::path& path, uint64_t max_bytes);

// The folder a glTF's relative URIs resolve against.
class SceneFolder {
 public:
  // No folder at all: every URI is refused (scenes uploaded as bytes).
  SceneFolder() = default;
  static Result<SceneFolder> at(const std::filesystem::path& folder);

  bool allows_files() const { return !root_.empty(); }
  const std::filesystem::path& root() const { return root_; }

  // `uri` is already percent-decoded. Succeeds with the file's canonical path when the URI is
  // a relative path naming an existing regular file inside the folder (symbolic links
  // resolved); the error says why not.
  Result<std::filesystem::path> resolve(const std::string& uri) const;

 private:
  std::filesystem::path root_;  // canonical; empty: none
};

// True when `path` is `root` or lies below it (both canonical).
bool is_within(const std::filesystem::path& path, const std::filesystem::path& root);

}  // namespace ddgi
