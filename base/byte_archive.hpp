// A minimal binary archive for the stage cache's port codecs (runtime/stage_cache.hpp): values
// are appended as their little-endian bytes, strings and arrays with a 64-bit length first. The
// reader checks every length against the bytes that remain, so a truncated or corrupt entry
// throws ArchiveError instead of allocating what a damaged length claims.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace gslift {

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE 754 floats expected");

struct ArchiveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_arithmetic_v<T>, "put() takes numbers; use the typed writers");
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_string(std::string_view s) {
    put<uint64_t>(s.size());
    bytes_.append(s.data(), s.size());
  }
  // Numbers in one block: the cost of a model's arrays is one memcpy each.
  template <class T>
  void put_array(const T* data, size_t count) {
    static_assert(std::is_arithmetic_v<T>, "put_array() takes numbers");
    put<uint64_t>(count);
    bytes_.append(reinterpret_cast<const char*>(data), count * sizeof(T));
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put_array(v.data(), v.size());
  }
  void put_strings(const std::vector<std::string>& v) {
    put<uint64_t>(v.size());
    for (const auto& s : v) put_string(s);
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}

  template <class T>
  T get() {
    static_assert(std::is_arithmetic_v<T>, "get() reads numbers");
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  // A count of items of `item_bytes` each, checked against what remains before anything is sized
  // by it.
  uint64_t count(size_t item_bytes) {
    const uint64_t n = get<uint64_t>();
    if (item_bytes > 0 && n > remaining() / item_bytes)
      throw ArchiveError("archive claims " + std::to_string(n) + " items but holds " +
                         std::to_string(remaining()) + " bytes");
    return n;
  }
  std::string get_string() {
    const uint64_t n = count(1);
    return std::string(take(n), n);
  }
  template <class T>
  std::vector<T> get_vector() {
    const uint64_t n = count(sizeof(T));
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
    return v;
  }
  // Reads an array into `data`, which must hold exactly `expected` items.
  template <class T>
  void get_array(T* data, size_t expected) {
    const uint64_t n = count(sizeof(T));
    if (n != expected)
      throw ArchiveError("archive array of " + std::to_string(n) + " items, expected " +
                         std::to_string(expected));
    if (n) std::memcpy(data, take(n * sizeof(T)), n * sizeof(T));
  }
  // Raw bytes after a count() the caller checked: images, whose layout the caller knows.
  void get_raw(void* data, size_t n) {
    if (n) std::memcpy(data, take(n), n);
  }
  std::vector<std::string> get_strings() {
    const uint64_t n = count(sizeof(uint64_t));
    std::vector<std::string> v;
    v.reserve(n);
    for (uint64_t i = 0; i < n; ++i) v.push_back(get_string());
    return v;
  }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool done() const { return pos_ == bytes_.size(); }

 private:
  const char* take(size_t n) {
    if (n > remaining())
      throw ArchiveError("archive truncated: " + std::to_string(n) + " bytes wanted, " +
                         std::to_string(remaining()) + " left");
    const char* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  std::string_view bytes_;
  size_t pos_ = 0;
};

}  // namespace gslift
