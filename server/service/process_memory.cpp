#include "service/process_memory.h"

#include <malloc.h>

#include "core/log.h"

namespace ddgi::service {

void limit_malloc_arenas(int arenas) {
  if (mallopt(M_ARENA_MAX, arenas) != 1) {
    LOG_WARNING << "mallopt(M_ARENA_MAX, " << arenas << ") failed; malloc arenas not capped";
  }
}

void release_free_memory() {
  malloc_trim(0);
}

}  // namespace ddgi::service
