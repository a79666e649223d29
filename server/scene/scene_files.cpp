#include "scene/scene_files.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace ddgi {
namespace fs = std::filesystem;

Result<std::vector<uint8_t>> read_file(const fs::path& path, uint64_t max_bytes) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) return not_found(path.string() + ": no such file");
  if (!fs::is_regular_file(status)) return invalid_argument(path.string() + ": not a regular file");
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) return invalid_argument(path.string() + ": cannot read its size: " + ec.message());
  if (size > max_bytes) {
    return resource_exhausted(path.string() + ": " + std::to_string(size) +
                              " bytes, more than the limit of " + std::to_string(max_bytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return invalid_argument(path.string() + ": cannot be opened");
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  // A file that shrank while being read is as broken as one that cannot be read.
  if (static_cast<uintmax_t>(in.gcount()) != size) {
    return invalid_argument(path.string() + ": read fewer bytes than its size");
  }
  return bytes;
}

bool is_within(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p) {
    // A trailing separator shows up as an empty last element: it matches anything.
    if (r->empty() && std::next(r) == root.end()) return true;
    if (p == path.end() || *p != *r) return false;
  }
  return true;
}

Result<SceneFolder> SceneFolder::at(const fs::path& folder) {
  std::error_code ec;
  fs::path root = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (ec || !fs::is_directory(root, ec)) {
    return not_found(folder.string() + ": not a folder");
  }
  SceneFolder result;
  result.root_ = std::move(root);
  return result;
}

Result<fs::path> SceneFolder::resolve(const std::string& uri) const {
  const std::string quoted = "'" + uri + "'";
  if (!allows_files()) {
    return invalid_argument("uri " + quoted +
                            " names a file, but a scene uploaded as bytes may not reference any "
                            "(embed it in the .glb)");
  }
  if (uri.empty()) return invalid_argument("empty uri");
  if (uri.find('\0') != std::string::npos) {
    return invalid_argument("uri " + quoted + " contains a NUL character");
  }
  // RFC 3986: a colon before the first slash makes the text before it a scheme (file:,
  // http:, an unsupported data: type, or a Windows drive letter).
  const size_t colon = uri.find(':');
  if (colon != std::string::npos && colon < uri.find('/')) {
    return invalid_argument("uri " + quoted +
                            " has a scheme; only relative file paths and base64 data URIs "
                            "(application/octet-stream, application/gltf-buffer, image/png, "
                            "image/jpeg) are supported");
  }
  if (uri.front() == '/') {
    return invalid_argument("uri " + quoted + " is an absolute path; it must be relative");
  }
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(root_ / uri, ec);
  if (ec) return invalid_argument("uri " + quoted + " cannot be resolved: " + ec.message());
  if (!is_within(resolved, root_)) {
    return invalid_argument("uri " + quoted + " resolves outside the scene folder " +
                            root_.string());
  }
  const fs::file_status status = fs::status(resolved, ec);
  if (ec || !fs::exists(status)) {
    return not_found("uri " + quoted + ": file not found in " + root_.string());
  }
  if (!fs::is_regular_file(status)) {
    return invalid_argument("uri " + quoted + " is not a regular file");
  }
  return resolved;
}

}  // namespace ddgi
