// Ids of 3 bytes, as the ED engine's cell map and calendar store them: 2^24 disk slots
// (CellGrid::kMaxDisks) in three quarters of the memory a 4-byte id takes, where those
// arrays are read at random and every byte counts against the cache.
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>

namespace grainflow::ed {

inline constexpr int kId24Bytes = 3;

// Reads 4 bytes and masks: the caller keeps at least one readable byte after the id.
inline int load_id24(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap32(v);
  return static_cast<int>(v & 0xFFFFFFu);
}

inline void store_id24(std::uint8_t* p, int v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
  p[2] = static_cast<std::uint8_t>(v >> 16);
}

}  // namespace grainflow::ed
