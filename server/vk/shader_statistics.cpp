// What the driver reports of each compiled pipeline (VK_KHR_pipeline_executable_properties):
// registers, shared memory, spills... A diagnostic for ddgi-bench --shader-stats, where a
// kernel's occupancy explains a time that its instruction count does not.
#include "vk/shader_statistics.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "vk/context.h"

namespace ddgi::vk {
namespace {

std::string statistic_value(const VkPipelineExecutableStatisticKHR& statistic) {
  char text[64];
  switch (statistic.format) {
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
      return statistic.value.b32 ? "yes" : "no";
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
      std::snprintf(text, sizeof(text), "%lld", static_cast<long long>(statistic.value.i64));
      return text;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
      std::snprintf(text, sizeof(text), "%llu",
                    static_cast<unsigned long long>(statistic.value.u64));
      return text;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR:
      std::snprintf(text, sizeof(text), "%g", statistic.value.f64);
      return text;
    default:
      return "?";
  }
}

}  // namespace

void Context::keep_shader_statistics(VkPipeline pipeline, const std::string& name) {
  if (!shader_statistics_enabled_) return;
  VkPipelineInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
  info.pipeline = pipeline;
  uint32_t count = 0;
  if (fn_.vkGetPipelineExecutablePropertiesKHR(device_, &info, &count, nullptr) != VK_SUCCESS) {
    return;  // a diagnostic: a driver that will not say leaves the table shorter
  }
  std::vector<VkPipelineExecutablePropertiesKHR> executables(
      count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
  if (fn_.vkGetPipelineExecutablePropertiesKHR(device_, &info, &count, executables.data()) !=
      VK_SUCCESS) {
    return;
  }
  std::vector<ShaderStatistic> kept;
  for (uint32_t e = 0; e < count; ++e) {
    VkPipelineExecutableInfoKHR executable{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
    executable.pipeline = pipeline;
    executable.executableIndex = e;
    uint32_t statistics = 0;
    if (fn_.vkGetPipelineExecutableStatisticsKHR(device_, &executable, &statistics, nullptr) !=
        VK_SUCCESS) {
      continue;
    }
    std::vector<VkPipelineExecutableStatisticKHR> values(
        statistics, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
    if (fn_.vkGetPipelineExecutableStatisticsKHR(device_, &executable, &statistics,
                                                 values.data()) != VK_SUCCESS) {
      continue;
    }
    for (const VkPipelineExecutableStatisticKHR& value : values) {
      kept.push_back({name, executables[e].name, value.name, statistic_value(value)});
    }
  }
  const std::lock_guard<std::mutex> lock(shader_statistics_mutex_);
  shader_statistics_.insert(shader_statistics_.end(), kept.begin(), kept.end());
}

std::vector<ShaderStatistic> Context::shader_statistics() const {
  const std::lock_guard<std::mutex> lock(shader_statistics_mutex_);
  return shader_statistics_;
}

std::string shader_statistics_table(const std::vector<ShaderStatistic>& statistics) {
  std::vector<std::string> names;
  std::vector<std::pair<std::string, std::string>> rows;  // pipeline, executable
  for (const ShaderStatistic& s : statistics) {
    if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
    const std::pair<std::string, std::string> row{s.pipeline, s.executable};
    if (std::find(rows.begin(), rows.end(), row) == rows.end()) rows.push_back(row);
  }
  if (rows.empty()) return "(the driver reported none)\n";
  std::string table = "| kernel | executable |";
  for (const std::string& name : names) table += " " + name + " |";
  table += "\n|---|---|";
  for (size_t i = 0; i < names.size(); ++i) table += "---|";
  table += "\n";
  for (const std::pair<std::string, std::string>& row : rows) {
    table += "| " + row.first + " | " + row.second + " |";
    for (const std::string& name : names) {
      const auto it = std::find_if(statistics.begin(), statistics.end(), [&](const auto& s) {
        return s.pipeline == row.first && s.executable == row.second && s.name == name;
      });
      table += it == statistics.end() ? " |" : " " + it->value + " |";
    }
    table += "\n";
  }
  return table;
}

}  // namespace ddgi::vk
