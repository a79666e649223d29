// The time budget's calibration cache, in memory and on disk (BudgetCache, tools/field_budget.h).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/hash.h"
#include "core/log.h"
#include "tools/field_budget.h"

namespace ddgi::tools {
namespace {

using nlohmann::json;

json to_json(const Calibration& c) {
  json candidates = json::array();
  for (const CalibratedCandidate& p : c.candidates) {
    candidates.push_back({{"name", p.candidate.name},
                          {"assignments", p.candidate.assignments},
                          {"shadow_ms", p.shadow_ms},
                          {"field_ms", p.field_ms},
                          {"frame_ms", p.frame_ms},
                          {"timed_frames", p.timed_frames},
                          {"flip", p.flip},
                          {"flip_noise", p.flip_noise},
                          {"mean_ratio", p.mean_ratio},
                          {"mean_ratio_noise", p.mean_ratio_noise}});
  }
  return {{"device", c.device},
          {"width", c.width},
          {"height", c.height},
          {"seconds", c.seconds},
          {"reference_mean", c.reference_mean},
          {"reference_noise", c.reference_noise},
          {"candidates", candidates}};
}

// Throws (nlohmann's exceptions) on a missing or mistyped field: the caller measures again.
Calibration from_json(const json& doc) {
  Calibration c;
  c.device = doc.at("device").get<std::string>();
  c.width = doc.at("width").get<uint32_t>();
  c.height = doc.at("height").get<uint32_t>();
  c.seconds = doc.at("seconds").get<double>();
  c.reference_mean = doc.at("reference_mean").get<double>();
  c.reference_noise = doc.at("reference_noise").get<double>();
  for (const json& p : doc.at("candidates")) {
    CalibratedCandidate point;
    point.candidate.name = p.at("name").get<std::string>();
    point.candidate.assignments = p.at("assignments").get<std::vector<std::string>>();
    point.shadow_ms = p.at("shadow_ms").get<double>();
    point.field_ms = p.at("field_ms").get<double>();
    point.frame_ms = p.at("frame_ms").get<double>();
    point.timed_frames = p.at("timed_frames").get<uint32_t>();
    point.flip = p.at("flip").get<double>();
    point.flip_noise = p.at("flip_noise").get<double>();
    point.mean_ratio = p.at("mean_ratio").get<double>();
    point.mean_ratio_noise = p.at("mean_ratio_noise").get<double>();
    c.candidates.push_back(std::move(point));
  }
  if (c.candidates.empty()) throw std::runtime_error("no candidates");
  return c;
}

}  // namespace

Status BudgetCache::persist_in(const std::string& dir) {
  std::error_code error;
  if (!dir.empty()) std::filesystem::create_directories(dir, error);
  if (error || (!dir.empty() && !std::filesystem::is_directory(dir))) {
    return invalid_argument("budget cache directory '" + dir +
                            "' cannot be created or is not a directory" +
                            (error ? ": " + error.message() : ""));
  }
  std::lock_guard lock(mutex_);
  dir_ = dir;
  return ok_status();
}

std::string BudgetCache::file_of(const std::string& key) const {
  char name[40];
  std::snprintf(name, sizeof name, "calibration-%016llx.json",
                static_cast<unsigned long long>(fnv1a(key)));
  return (std::filesystem::path(dir_) / name).string();
}

std::optional<Calibration> BudgetCache::read_file(const std::string& key) const {
  const std::string path = file_of(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    const json doc = json::parse(in);
    // The key is kept whole: two keys of one hash never take each other's calibration.
    if (doc.at("key").get<std::string>() != key) return std::nullopt;
    return from_json(doc.at("calibration"));
  } catch (const std::exception& e) {
    LOG_WARNING << "budget cache: " << path << " is unreadable (" << e.what()
                << "); calibrating again";
    return std::nullopt;
  }
}

void BudgetCache::write_file(const std::string& key, const Calibration& calibration) const {
  const std::string path = file_of(key);
  // A name of this process's own: servers sharing the directory never write into one file.
  const std::string partial = path + ".partial." + std::to_string(::getpid());
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out << json{{"key", key}, {"calibration", to_json(calibration)}}.dump(1) << "\n";
    if (!out) {
      LOG_WARNING << "budget cache: cannot write " << partial << "; kept in memory only";
      return;
    }
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    LOG_WARNING << "budget cache: cannot rename to " << path << ": " << error.message();
  }
}

std::optional<Calibration> BudgetCache::find(const std::string& key) {
  std::lock_guard lock(mutex_);
  if (const auto it = entries_.find(key); it != entries_.end()) return it->second;
  if (dir_.empty()) return std::nullopt;
  std::optional<Calibration> kept = read_file(key);
  if (kept) entries_[key] = *kept;
  return kept;
}

void BudgetCache::put(const std::string& key, const Calibration& calibration) {
  std::lock_guard lock(mutex_);
  entries_[key] = calibration;
  if (!dir_.empty()) write_file(key, calibration);
}

Result<Calibration> BudgetCache::get_or_measure(const std::string& key, const Measure& measure,
                                                bool& from_cache) {
  if (std::optional<Calibration> kept = find(key)) {
    from_cache = true;
    return *kept;
  }
  // Measured outside the lock: another scene's session need not wait for this one.
  DDGI_ASSIGN_OR_RETURN(Calibration calibration, measure());
  put(key, calibration);
  from_cache = false;
  return calibration;
}

}  // namespace ddgi::tools
