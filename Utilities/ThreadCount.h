// The OpenMP thread count a run may ask for. More threads than 4x the hardware's only wait for
// each other, and the OpenMP runtime crashes creating ~1e5 of them (each has its own stack), so
// a larger request is clamped (the CLI's --threads, Python's set_num_threads).
#pragma once
#include <string>

namespace consph {

// min(1024, 4 x hardware threads).
int maxThreadCount();

// `requested` (>= 1) clamped to maxThreadCount(); when clamped, `warning` says so.
int clampThreadCount(long long requested, std::string& warning);

}  // namespace consph
