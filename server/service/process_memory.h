// glibc malloc and a server whose sessions come and go. Each session loads its scene and runs
// its frame loop on a thread of its own, and glibc gives busy threads arenas of their own (up to
// 8 per core); what a closed session freed stays in those arenas, resident, until something
// hands it back. Measured (MemoryReturnTest): without the trim, +185 to +193 MiB resident after
// three rounds of three 5.8 MB uploads, every session closed; with it, +8 to +19 MiB. The issue
// saw ~1 GiB.
#pragma once

namespace ddgi::service {

// ddgi-server's malloc arena cap: 4, in [1, 8 x cores] (glibc's own cap is 8 per core). Fewer
// arenas keep less freed memory resident between sessions; one would serialize every session's
// allocations on one lock.
inline constexpr int kServerMallocArenas = 4;

// Caps the number of malloc arenas (mallopt M_ARENA_MAX). Call before threads start: glibc
// fixes the cap once it first needs more than its initial few arenas.
void limit_malloc_arenas(int arenas);

// Returns free memory of every arena to the system (malloc_trim). A few milliseconds; called
// when a session's frame loop has freed everything it held.
void release_free_memory();

}  // namespace ddgi::service
