#include "Common/Memory.h"

#include <cstdlib>  // brings in the C library's feature macros (__GLIBC__)
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace vs {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 256 << 20);  // blocks up to 256 MiB come from the heap
  mallopt(M_TRIM_THRESHOLD, 1 << 30);    // free heap is kept up to 1 GiB
#endif
}

}  // namespace vs
