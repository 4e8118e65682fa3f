// The two 64-bit hashes of the project, in one place. Both are fully specified integer
// arithmetic, so they give the same bits with any compiler and standard library (std::hash does
// not: it may differ between builds).
#pragma once

#include <cstdint>
#include <string_view>

namespace gslift {

// FNV-1a, 64 bit (Fowler, Noll, Vo; the IETF draft "The FNV Non-Cryptographic Hash Algorithm"):
// a stable hash of a byte string (node ids, text features, settings texts).
constexpr uint64_t kFnv1a64Basis = 0xcbf29ce484222325ull;  // the hash of no bytes

// FNV-1a continued from the hash `h` of the bytes before `text`, for data read in pieces
// (a file streamed through a buffer): fnv1a64(ab) == fnv1a64_update(fnv1a64(a), b).
constexpr uint64_t fnv1a64_update(uint64_t h, std::string_view text) {
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;  // FNV prime
  }
  return h;
}

constexpr uint64_t fnv1a64(std::string_view text) {
  return fnv1a64_update(kFnv1a64Basis, text);
}

// SplitMix64's output function (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number
// generators"; constants of Vigna's splitmix64.c): add the golden-ratio increment, then a
// bijective mix, so distinct inputs give distinct, unrelated outputs.
constexpr uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace gslift
