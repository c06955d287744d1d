#pragma once
// Frames are megabytes each (a 1242x375 colour image 1.4 MB, its depth 1.8 MB, its pyramid 3.3 MB) and
// every stage allocates and frees them, on several threads. glibc serves such blocks from fresh mappings
// (or trims them from its heaps when freed), so every frame pays a page fault per 4 KiB it touches: in
// `serve` at 10 Hz that was the input stage's median (12.7 -> 1.2 ms, bench_dds_latency) and the tail of
// every stage. Programs that stream frames call this once at start, before their threads.

namespace dslam {

// Blocks up to 32 MiB (glibc's largest mmap threshold) come from malloc's heaps and are reused; a heap
// keeps up to 256 MiB of free memory at its top instead of returning it. Memory stays bounded by the
// largest working set the program had (it is reused, not leaked). Returns false where the C library
// refused (not glibc), which only costs speed.
bool KeepFrameBuffersInHeap();

}  // namespace dslam
