// What a scene may ask of this machine: the engines' cross-checks estimate the memory a
// scene needs (particles × bytes per particle) and refuse, before any set-up, a scene that
// cannot fit — with the estimate and the machine's memory in the message — instead of
// ending in bad_alloc or swapping for minutes.
#pragma once
#include <cstdint>
#include <string>

namespace grainflow::scenes {

// Physical memory of this machine [bytes] (sysconf); 0 when unknown.
std::uint64_t physical_memory_bytes();

// "" when `count` items of `bytes_per_item` fit in 80 % of the machine's memory; otherwise
// the sentence to report: "this scene needs ≈ 41 GB for 2.6e+09 disks; this machine has
// 23 GB". `what` names the items ("disks", "spheres").
std::string memory_shortfall(double count, double bytes_per_item, const std::string& what);

}  // namespace grainflow::scenes
