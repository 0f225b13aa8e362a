// Live and peak heap bytes of the whole process, for the benchmarks' memory columns.
//
// Linking heap_counter.cc (the femsimp_bench_heap object library) replaces the global operator
// new/delete with counting versions: the figures are malloc_usable_size bytes of every block
// allocated through operator new, so allocator caching can neither hide nor inflate them. The
// engine, OpenMesh and meshoptimizer (whose default allocator is ::operator new) all allocate
// that way, so nothing they use is missed.
#pragma once

#include <cstdint>

namespace femsimp::bench {

int64_t LiveHeapBytes();
int64_t PeakHeapBytes();
// Starts a new peak at the current live level.
void ResetHeapPeak();

}  // namespace femsimp::bench
