// The lights of a session with the ids clients know them by. A scene's own lights get ids
// 0..n-1, added ones the next free id; ids are never reused while the scene stays. Every change
// is handed to an upload function (the GPU scene's light table) and undone when it fails, so
// the set always matches what the GPU has.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"

namespace ddgi::service {

struct LightSlot {
  uint32_t id = 0;
  Light light;
};

class LightSet {
 public:
  // Makes the GPU hold `lights` (in id order).
  using Upload = std::function<Status(const std::vector<Light>& lights)>;

  LightSet() = default;
  explicit LightSet(const std::vector<Light>& scene_lights);

  const std::vector<LightSlot>& slots() const { return slots_; }
  size_t size() const { return slots_.size(); }
  // Null when no light has `id`.
  const LightSlot* find(uint32_t id) const;

  // Each returns the light as it is now (for remove: as it was); the set is unchanged when
  // `upload` fails.
  Result<LightSlot> add(const Light& light, const Upload& upload);
  Result<LightSlot> update(uint32_t id, const Light& light, const Upload& upload);
  Result<LightSlot> remove(uint32_t id, const Upload& upload);

 private:
  std::vector<Light> lights() const;

  std::vector<LightSlot> slots_;  // in id order
  uint32_t next_id_ = 0;
};

}  // namespace ddgi::service
