// What a driver reports of the pipelines it compiled (VK_KHR_pipeline_executable_properties,
// kept by Context when ContextOptions::shader_statistics asks), and the table ddgi-bench
// --shader-stats prints of them.
#pragma once

#include <string>
#include <vector>

namespace ddgi::vk {

// One statistic of one compiled pipeline's executable (a shader stage, or part of one), e.g.
// ("field_blend", "Compute Shader", "Register Count", "40").
struct ShaderStatistic {
  std::string pipeline;
  std::string executable;
  std::string name;
  std::string value;
};

// A markdown table: one row per pipeline and executable (in the order first seen), one column
// per statistic name (in the order first seen; drivers name them differently), empty cells
// where an executable lacks one.
std::string shader_statistics_table(const std::vector<ShaderStatistic>& statistics);

}  // namespace ddgi::vk
