// A fingerprint of an engine's state: FNV-1a (64 bit) over the exact bit patterns of its
// numbers, so two runs that must agree bit for bit (same seed, chain cells vs the N²
// search, 1 vs 2 threads) can be compared from their run.json alone.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

namespace grainflow::core {

class StateDigest {
public:
  void add(std::uint64_t word) {
    for (int b = 0; b < 8; ++b) {
      h_ ^= (word >> (8 * b)) & 0xffu;
      h_ *= 0x100000001b3ull;
    }
  }
  void add(double x) { add(std::bit_cast<std::uint64_t>(x)); }
  void add(std::span<const double> xs) {
    for (double x : xs) add(x);
  }
  // Raw bytes (the checkpoint container's checksum).
  void add_bytes(std::span<const std::byte> bytes) {
    for (std::byte b : bytes) {
      h_ ^= static_cast<std::uint64_t>(b);
      h_ *= 0x100000001b3ull;
    }
  }
  std::uint64_t value() const { return h_; }
  std::string hex() const {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
    return buf;
  }

private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;  // FNV offset basis
};

}  // namespace grainflow::core
