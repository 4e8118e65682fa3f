// A std::vector that leaves the new elements of a resize uninitialised.
#pragma once

#include <memory>
#include <utility>
#include <vector>

namespace gslift {

// std::vector whose resize leaves new elements of trivial types uninitialised: for the large
// per-view arrays that parallel loops overwrite entirely, where zeroing them first would be a
// serial pass over memory (taking all the page faults on one thread).
template <class T>
struct NoInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using UninitVector = std::vector<T, NoInitAllocator<T>>;

}  // namespace gslift
