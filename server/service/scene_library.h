// The server's scene library: a configured root folder whose .gltf / .glb / .ddgi.json files are
// offered by name ("cornell_box"). Clients only ever pick a name from the folder's listing; a
// name is never joined into a path, so "../x", "/etc/passwd" or "a\0b" cannot reach a file.
#pragma once

#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::service {

class SceneLibrary {
 public:
  explicit SceneLibrary(std::string root) : root_(std::move(root)) {}

  const std::string& root() const { return root_; }
  // Sorted scene names, read from the folder now (files added later show up).
  std::vector<std::string> names() const;
  // The file behind `name`: INVALID_ARGUMENT for malformed or path-like names, NOT_FOUND for
  // names not in the listing.
  Result<std::string> resolve(const std::string& name) const;

 private:
  struct Entry {
    std::string name;
    std::string path;
  };
  std::vector<Entry> list() const;

  std::string root_;
};

// Checks the form of a name before any lookup: 1..128 bytes of letters, digits, '_', '-', '.',
// not starting with '.'; NUL bytes, '/', '\' and ".." are rejected as path-like.
Status validate_scene_name(const std::string& name);

}  // namespace ddgi::service
