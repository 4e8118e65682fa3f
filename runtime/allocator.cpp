#include "runtime/allocator.hpp"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace gslift {

void keep_freed_memory_in_process() {
#if defined(__GLIBC__)
  // Setting either value also turns off glibc's dynamic threshold, so both are set explicitly.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace gslift
