// Whole-file reads and writes whose errors name the file and the OS reason.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::encode {

Status write_file(const std::string& path, std::span<const uint8_t> bytes);
Result<std::vector<uint8_t>> read_file(const std::string& path);

}  // namespace ddgi::encode
