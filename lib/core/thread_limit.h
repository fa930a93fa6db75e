#pragma once
// The most worker threads a run may ask for (render.threads, --threads, Python's threads=): far
// above any machine's cores, low enough that a typo fails with a message instead of
// std::bad_alloc from a scheduler sized for a billion threads.
namespace vpm {

constexpr int kMaxThreads = 4096;

}  // namespace vpm
