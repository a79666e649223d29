// A session's lights and their ids (service/light_set.h).
#include "service/light_set.h"

#include <algorithm>
#include <string>

namespace ddgi::service {

LightSet::LightSet(const std::vector<Light>& scene_lights) {
  for (const Light& light : scene_lights) slots_.push_back({next_id_++, light});
}

const LightSlot* LightSet::find(uint32_t id) const {
  auto it = std::find_if(slots_.begin(), slots_.end(),
                         [&](const LightSlot& slot) { return slot.id == id; });
  return it == slots_.end() ? nullptr : &*it;
}

std::vector<Light> LightSet::lights() const {
  std::vector<Light> lights;
  for (const LightSlot& slot : slots_) lights.push_back(slot.light);
  return lights;
}

Result<LightSlot> LightSet::add(const Light& light, const Upload& upload) {
  slots_.push_back({next_id_, light});
  const Status status = upload(lights());
  if (!status.ok()) {
    slots_.pop_back();
    return status.error();
  }
  ++next_id_;
  return slots_.back();
}

Result<LightSlot> LightSet::update(uint32_t id, const Light& light, const Upload& upload) {
  auto it = std::find_if(slots_.begin(), slots_.end(),
                         [&](const LightSlot& slot) { return slot.id == id; });
  if (it == slots_.end()) return not_found("no light " + std::to_string(id));
  const Light old = it->light;
  it->light = light;
  const Status status = upload(lights());
  if (!status.ok()) {
    it->light = old;
    return status.error();
  }
  return *it;
}

Result<LightSlot> LightSet::remove(uint32_t id, const Upload& upload) {
  auto it = std::find_if(slots_.begin(), slots_.end(),
                         [&](const LightSlot& slot) { return slot.id == id; });
  if (it == slots_.end()) return not_found("no light " + std::to_string(id));
  const LightSlot removed = *it;
  const auto position = slots_.erase(it);
  const Status status = upload(lights());
  if (!status.ok()) {
    slots_.insert(position, removed);
    return status.error();
  }
  return removed;
}

}  // namespace ddgi::service
