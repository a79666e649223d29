// Parallel loops for the metrics. Scoring a 1080p frame is two FLIPs and an SSIM, each a dozen
// wide convolutions and a few million colour conversions; on a 16-core GPU host single-threaded
// scoring left the GPU idle for most of a Pareto sweep. Every element is computed by the same
// code whichever thread runs it, and sums are reduced per chunk in chunk order, so results do
// not depend on the number of threads.
#pragma once

#include <cstddef>
#include <functional>

namespace ddgi::metrics {

// Runs body(begin, end) over [0, count) in chunks of `chunk` elements (the last may be shorter),
// spread over a process-wide pool of hardware_concurrency() - 1 threads and the caller.
void for_each_chunk(size_t count, size_t chunk, const std::function<void(size_t, size_t)>& body);

}  // namespace ddgi::metrics
