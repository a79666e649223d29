#include "service/scene_library.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <system_error>

#include "service/text.h"

namespace ddgi::service {
namespace {

constexpr size_t kMaxNameBytes = 128;

// Longest suffix first: "x.ddgi.json" is the scene "x".
const char* const kSuffixes[] = {".ddgi.json", ".gltf", ".glb"};

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A glTF file wins over its own sidecar: load_scene applies the sidecar beside it anyway.
int preference(const std::string& filename) {
  if (ends_with(filename, ".gltf") || ends_with(filename, ".glb")) return 0;
  return 1;
}

bool name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-' || c == '.';
}

bool path_may_start_after(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\'' || c == '"' || c == '`' || c == '(' ||
         c == '[' || c == '=' || c == ',';
}

bool path_ends_at(const std::string& text, size_t i) {
  const char c = text[i];
  if (c == ' ' || c == '\t' || c == '\n' || c == '\'' || c == '"' || c == '`' || c == ')' ||
      c == ']' || c == ',' || c == ';') {
    return true;
  }
  return c == ':' && (i + 1 == text.size() || text[i + 1] == ' ');
}

}  // namespace

std::string redact_paths(const std::string& text, const std::vector<std::string>& roots,
                         const std::string& root_label) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    const bool starts = text[i] == '/' && (i == 0 || path_may_start_after(text[i - 1])) &&
                        i + 1 < text.size() && !path_ends_at(text, i + 1);
    if (!starts) {
      out += text[i++];
      continue;
    }
    size_t end = i;
    while (end < text.size() && !path_ends_at(text, end)) ++end;
    const std::string path = text.substr(i, end - i);
    std::string shown;
    for (const std::string& root : roots) {
      if (path == root || path == root + "/") {
        shown = root_label;
        break;
      }
      if (path.size() > root.size() + 1 && path.compare(0, root.size(), root) == 0 &&
          path[root.size()] == '/') {
        shown = root_label + path.substr(root.size());
        break;
      }
    }
    if (shown.empty()) {
      std::string name = path;
      while (!name.empty() && name.back() == '/') name.pop_back();
      name = name.substr(name.find_last_of('/') + 1);
      shown = name.empty() ? "..." : ".../" + name;
    }
    out += shown;
    i = end;
  }
  return out;
}

Status validate_scene_name(const std::string& name) {
  if (name.empty()) return invalid_argument("scene name is empty");
  if (name.size() > kMaxNameBytes) {
    return invalid_argument("scene name is " + std::to_string(name.size()) +
                            " bytes long; at most " + std::to_string(kMaxNameBytes) +
                            " are allowed");
  }
  if (name.find('\0') != std::string::npos) {
    return invalid_argument("scene name " + printable(name) +
                            " contains a NUL byte; names come from the library listing "
                            "(GetServerInfo.scenes)");
  }
  if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos ||
      name.find("..") != std::string::npos || name.front() == '.') {
    return invalid_argument("scene name " + printable(name) +
                            " looks like a path; give a name from the library listing "
                            "(GetServerInfo.scenes), not a file path");
  }
  for (char c : name) {
    if (!name_char(c)) {
      return invalid_argument("scene name " + printable(name) +
                              " has a character other than letters, digits, '_', '-' and '.'");
    }
  }
  return ok_status();
}

std::vector<SceneLibrary::Entry> SceneLibrary::list() const {
  std::map<std::string, std::pair<int, std::string>> found;  // name -> (preference, path)
  std::error_code ec;
  for (std::filesystem::directory_iterator it(root_, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string filename = it->path().filename().string();
    for (const char* suffix : kSuffixes) {
      if (!ends_with(filename, suffix)) continue;
      const std::string name = filename.substr(0, filename.size() - std::string(suffix).size());
      if (!validate_scene_name(name).ok()) break;  // a file we could never name: not offered
      const int rank = preference(filename);
      auto existing = found.find(name);
      if (existing == found.end() || rank < existing->second.first) {
        found[name] = {rank, it->path().string()};
      }
      break;
    }
  }
  std::vector<Entry> entries;
  for (auto& [name, value] : found) entries.push_back({name, value.second});
  return entries;
}

std::vector<std::string> SceneLibrary::names() const {
  std::vector<std::string> names;
  for (const Entry& entry : list()) names.push_back(entry.name);
  return names;
}

Result<std::string> SceneLibrary::resolve(const std::string& name) const {
  DDGI_TRY(validate_scene_name(name));
  const std::vector<Entry> entries = list();
  for (const Entry& entry : entries) {
    if (entry.name == name) return entry.path;
  }
  return not_found("no scene named " + printable(name) + " in the scene library (" +
                   std::to_string(entries.size()) + " scenes; GetServerInfo.scenes lists them)");
}

Error SceneLibrary::without_server_paths(const Error& error) const {
  // The root as configured, made absolute, and with every symbolic link resolved (the loader
  // names files by their canonical paths); the longest first, so that a root inside another
  // is tried before it.
  std::vector<std::string> roots;
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(root_, ec);
  for (std::filesystem::path root :
       {std::filesystem::path(root_), absolute, std::filesystem::weakly_canonical(absolute, ec)}) {
    std::string text = root.lexically_normal().string();
    while (text.size() > 1 && text.back() == '/') text.pop_back();
    if (!text.empty() && text.front() == '/' && text != "/") roots.push_back(text);
  }
  std::sort(roots.begin(), roots.end(),
            [](const std::string& a, const std::string& b) { return a.size() > b.size(); });
  return Error{error.code, redact_paths(error.message, roots, "<library>")};
}

}  // namespace ddgi::service
