// Binary archives for checkpoints: a writer that appends plain values and arrays to a
// byte string, and a reader that takes them back in the same order and refuses to read
// past the end or to reserve more than the bytes left could hold (a corrupt length must
// not become a huge allocation). Native byte order and layout: a checkpoint is read back
// by the same build on the same kind of machine (the container, checkpoint_file.hpp,
// records the format version and refuses another).
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "engine/core/error.hpp"
#include "engine/core/binning.hpp"
#include "engine/core/rng.hpp"

namespace grainflow::io {

class ArchiveWriter {
public:
  ArchiveWriter() = default;
  // Writes into `buffer`, emptied but keeping its capacity: a run that checkpoints often
  // reuses one buffer instead of faulting in fresh pages for every checkpoint.
  explicit ArchiveWriter(std::string buffer) : bytes_(std::move(buffer)) { bytes_.clear(); }
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  // Any contiguous container of trivially copyable values (std::vector, HugeVector).
  template <class C>
  void array(const C& v) {
    using T = typename C::value_type;
    static_assert(std::is_trivially_copyable_v<T>);
    pod(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void string(std::string_view s) {
    pod(static_cast<std::uint64_t>(s.size()));
    bytes_.append(s.data(), s.size());
  }
  // A named section marker: the reader checks it, so a reader and writer that disagree on
  // what comes next fail at the first section instead of reading garbage.
  void tag(std::string_view name) { string(name); }
  // bool as one byte 0/1 (read back by ArchiveReader::flag, which checks it).
  void flag(bool b) { pod(static_cast<std::uint8_t>(b ? 1 : 0)); }
  // A random stream, field by field: Rng::State has padding after its bool, and the same
  // state must always give the same bytes.
  void rng(const core::Rng& r) {
    const core::Rng::State st = r.state();
    pod(st.s);
    flag(st.has_spare);
    pod(st.spare);
  }
  // Room for `n` more bytes (a large state is written without regrowing the buffer).
  void reserve(std::size_t n) { bytes_.reserve(bytes_.size() + n); }

  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

private:
  std::string bytes_;
};

class ArchiveReader {
public:
  // `what` names the source in errors ("checkpoint run/checkpoints/000004.gfck").
  ArchiveReader(std::string_view bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <class T>
  void pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
  }
  template <class T>
  T get() {
    T v{};
    pod(v);
    return v;
  }
  template <class C>
  void array(C& v) {
    using T = typename C::value_type;
    static_assert(std::is_trivially_copyable_v<T>);
    const std::uint64_t n = get<std::uint64_t>();
    if (n > left() / sizeof(T))
      throw Error(what_ + " is truncated or corrupt: an array of " + std::to_string(n) + " entries, " + std::to_string(left()) + " bytes left");
    v.resize(static_cast<std::size_t>(n));
    if (n) std::memcpy(static_cast<void*>(v.data()), bytes_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
  }
  // Reads an array that must have exactly `n` entries (the size a rebuilt state has).
  template <class C>
  void array_of(C& v, std::size_t n, std::string_view name) {
    array(v);
    if (v.size() != n) corrupt(std::string(name) + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
  }
  std::string string() {
    const std::uint64_t n = get<std::uint64_t>();
    if (n > left()) throw Error(what_ + " is truncated or corrupt: a block of " + std::to_string(n) + " bytes, " + std::to_string(left()) + " left");
    std::string s(bytes_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  void tag(std::string_view name) {
    const std::string got = string();
    if (got != name) mismatch("expected section '" + std::string(name) + "', found '" + got + "'");
  }
  bool flag(std::string_view what) {
    const auto v = get<std::uint8_t>();
    if (v > 1) corrupt(std::string(what) + " is " + std::to_string(v) + ", not a flag (0 or 1)");
    return v == 1;
  }
  void rng(core::Rng& r) {
    core::Rng::State st{};
    pod(st.s);
    st.has_spare = flag("a random stream's spare flag");
    pod(st.spare);
    r.set_state(st);
  }

  std::size_t left() const { return bytes_.size() - pos_; }
  bool at_end() const { return pos_ == bytes_.size(); }
  // The whole archive must have been read: bytes left over mean the writer wrote more.
  void expect_end() const {
    if (!at_end()) mismatch(std::to_string(left()) + " bytes left over after the last section");
  }
  // The saved state does not fit the state being restored (another scene, another build).
  [[noreturn]] void mismatch(const std::string& why) const {
    throw Error(what_ + " does not match this run: " + why);
  }
  [[noreturn]] void corrupt(const std::string& why) const { throw Error(what_ + " is corrupt: " + why); }

private:
  void need(std::size_t n) const {
    if (n > left()) throw Error(what_ + " is truncated: " + std::to_string(n) + " bytes needed at offset " + std::to_string(pos_) + ", " + std::to_string(left()) + " left");
  }
  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::string what_;
};

// Binned-field accumulators (the samplers' partial exposures).
inline void save(ArchiveWriter& w, const core::BinAccumulator& acc) {
  const core::BinAccumulator::State st = acc.state();
  w.tag("bins");
  for (int v : {st.dim, st.frames}) w.pod(v);
  for (bool b : {st.frame_vel, st.frame_rad, st.all_vel, st.all_rad, st.all_slab}) w.flag(b);
  w.pod(st.slab_sum);
  w.pod(st.outside);
  w.array(st.count);
  for (const auto* v : {&st.mass, &st.vol, &st.speed, &st.msq, &st.mom}) w.array(*v);
}
inline void load(ArchiveReader& r, core::BinAccumulator& acc) {
  core::BinAccumulator::State st;
  r.tag("bins");
  for (int* v : {&st.dim, &st.frames}) r.pod(*v);
  for (bool* b : {&st.frame_vel, &st.frame_rad, &st.all_vel, &st.all_rad, &st.all_slab}) *b = r.flag("a binning flag");
  r.pod(st.slab_sum);
  r.pod(st.outside);
  r.array(st.count);
  for (auto* v : {&st.mass, &st.vol, &st.speed, &st.msq, &st.mom}) r.array(*v);
  try {
    acc.set_state(st);
  } catch (const Error& e) {
    r.mismatch(e.what());
  }
}

}  // namespace grainflow::io
