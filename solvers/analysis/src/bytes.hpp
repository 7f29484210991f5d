#pragma once
// Values as bytes for an MPI gather, bit for bit (doubles are copied, not printed). Private to the
// analysis library: the samples of a tolerance run and the evaluations of an optimisation.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace ltca::analysis::bytes {

template <typename T>
void Put(std::string& out, const T& v) {
  static_assert(std::is_trivially_copyable_v<T>);
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
T Take(const std::string& in, std::size_t& at) {
  static_assert(std::is_trivially_copyable_v<T>);
  if (at + sizeof(T) > in.size()) throw std::runtime_error("gathered bytes are truncated");
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

inline void PutString(std::string& out, const std::string& s) {
  Put(out, static_cast<std::uint64_t>(s.size()));
  out += s;
}

inline std::string TakeString(const std::string& in, std::size_t& at) {
  const auto n = Take<std::uint64_t>(in, at);
  if (n > in.size() - at) throw std::runtime_error("gathered bytes are truncated");
  std::string s = in.substr(at, static_cast<std::size_t>(n));
  at += static_cast<std::size_t>(n);
  return s;
}

}  // namespace ltca::analysis::bytes
