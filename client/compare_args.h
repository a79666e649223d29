// Command line of ddgi-compare.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace ddgi::client {

struct CompareArgs {
  std::string reference;
  std::string test;
  std::optional<std::string> flip_map;  // where to write the colour-mapped FLIP error image
  double ppd = 67.0;                    // FLIP's viewing condition, the paper's default monitor
  double exposure = 0.0;                // stops applied to HDR inputs before clipping to [0,1]
  bool json = false;                    // one JSON object on stdout instead of a table
  bool help = false;
};

// The usage text, also the --help output; it documents every convention the tool uses.
std::string compare_usage();

Result<CompareArgs> parse_compare_args(const std::vector<std::string>& args);

}  // namespace ddgi::client
