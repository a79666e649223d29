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
  // An error of loading a library scene as a client may see it: no absolute server path.
  // Paths inside the library are shown below "<library>" ("<library>/room.gltf: uri 'a.bin':
  // file not found in <library>"); any other absolute path keeps only its file name
  // (".../sky.exr").
  Error without_server_paths(const Error& error) const;

 private:
  struct Entry {
    std::string name;
    std::string path;
  };
  std::vector<Entry> list() const;

  std::string root_;
};

// `text` with every absolute path replaced: one of `roots` (absolute, without a trailing '/')
// by `root_label`, also where it begins a longer path (root_label + "/sub/x.gltf"), anything
// else by ".../" and its last component. A path starts with '/' at the start of the text or after a
// space, quote, '(', '[', '=' or ','; it ends at whitespace, a quote, ')', ']', ',', ';' or a
// ':' that ends the text or precedes a space.
std::string redact_paths(const std::string& text, const std::vector<std::string>& roots,
                         const std::string& root_label);

// Checks the form of a name before any lookup: 1..128 bytes of letters, digits, '_', '-', '.',
// not starting with '.'; NUL bytes, '/', '\' and ".." are rejected as path-like.
Status validate_scene_name(const std::string& name);

}  // namespace ddgi::service
