#include "encode/file_io.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace ddgi::encode {

namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

std::string os_reason() {
  return std::strerror(errno);
}

}  // namespace

Status write_file(const std::string& path, std::span<const uint8_t> bytes) {
  FilePtr file(std::fopen(path.c_str(), "wb"));
  if (!file) return failed_precondition(path + ": cannot open for writing: " + os_reason());
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
    return failed_precondition(path + ": write failed: " + os_reason());
  }
  // fclose flushes; a full disk often only shows up here.
  if (std::fclose(file.release()) != 0) {
    return failed_precondition(path + ": write failed: " + os_reason());
  }
  return ok_status();
}

Result<std::vector<uint8_t>> read_file(const std::string& path) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    const bool missing = errno == ENOENT;
    const std::string message = path + ": cannot open for reading: " + os_reason();
    return missing ? not_found(message) : failed_precondition(message);
  }
  std::vector<uint8_t> bytes;
  uint8_t chunk[1 << 16];
  size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof(chunk), file.get())) > 0) {
    bytes.insert(bytes.end(), chunk, chunk + got);
  }
  if (std::ferror(file.get())) return failed_precondition(path + ": read failed: " + os_reason());
  return bytes;
}

}  // namespace ddgi::encode
