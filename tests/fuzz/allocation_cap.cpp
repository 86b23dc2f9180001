// Linked into the vdb fuzz target and the replay tests (issue 21): OpenVDB 10
// allocates a compressed block's size as read from the file (io::bloscFromStream) before reading it. In a
// release build an impossible size throws std::bad_alloc, which load_vdb
// turns into one line; under ASan a throwing new that cannot allocate
// aborts instead. These replacements throw std::bad_alloc above
// SVO_FUZZ_ALLOCATION_CAP bytes, as a release build does beyond the
// address space, and otherwise allocate with malloc (ASan still guards it).
// They also keep the largest size asked for, which the replay tests bound
// per input (a 105-byte .hdr once made OpenImageIO ask for 3.4 GB).
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

#ifndef SVO_FUZZ_ALLOCATION_CAP
#define SVO_FUZZ_ALLOCATION_CAP 0x10000000000ull  // 1 TiB, ASan's largest allocation
#endif

namespace {
std::atomic<size_t> largest{0};  // the largest allocation asked for since the last reset

void* allocate(size_t n) {
  for (size_t seen = largest.load(std::memory_order_relaxed);
       n > seen && !largest.compare_exchange_weak(seen, n, std::memory_order_relaxed);) {
  }
  if (n > size_t(SVO_FUZZ_ALLOCATION_CAP)) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

// The replay tests bound what one input may ask for (allocation_cap.h).
size_t svo_fuzz_largest_allocation_and_reset() { return largest.exchange(0, std::memory_order_relaxed); }

void* operator new(size_t n) { return allocate(n); }
void* operator new[](size_t n) { return allocate(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }
