// Replaces the global operator new of the test binary with one that counts calls, so that a
// test can assert that a code path allocates nothing, and the bytes live and their peak
// (malloc_usable_size of each block), so that a test can bound what a code path holds at once.
// Kept in its own file so that no other translation unit sees the replacement's definition.
//
// Every replaceable form is replaced (plain, array, nothrow, aligned, sized), all on malloc /
// aligned_alloc and free: a form left to the runtime would allocate with another allocator
// than the free() below releases with, which AddressSanitizer reports as a mismatch (PoCL's
// compiler uses the nothrow forms).
#include "alloc_counter.hpp"

#include <malloc.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<long> allocations{0};
std::atomic<long> live_bytes{0};
std::atomic<long> peak_bytes{0};

void* Counted(void* p) noexcept {
  if (p == nullptr) return p;
  const long size = long(malloc_usable_size(p));
  const long live = live_bytes.fetch_add(size) + size;
  long peak = peak_bytes.load(std::memory_order_relaxed);
  while (live > peak && !peak_bytes.compare_exchange_weak(peak, live)) {
  }
  return p;
}

void Release(void* p) noexcept {
  if (p == nullptr) return;
  live_bytes.fetch_sub(long(malloc_usable_size(p)));
  std::free(p);
}

void* Allocate(std::size_t size) noexcept {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return Counted(std::malloc(size == 0 ? 1 : size));
}

void* AllocateAligned(std::size_t size, std::align_val_t align) noexcept {
  allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(align);
  const std::size_t rounded = (size == 0 ? a : (size + a - 1) / a * a);  // aligned_alloc's rule
  return Counted(std::aligned_alloc(a, rounded));
}

}  // namespace

long AllocationCount() { return allocations.load(); }
long LiveHeapBytes() { return live_bytes.load(); }
long PeakHeapBytes() { return peak_bytes.load(); }
void ResetPeakHeapBytes() { peak_bytes.store(live_bytes.load()); }

void* operator new(std::size_t size) {
  if (void* p = Allocate(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return Allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return Allocate(size); }
void* operator new(std::size_t size, std::align_val_t align) {
  if (void* p = AllocateAligned(size, align)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) { return operator new(size, align); }
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return AllocateAligned(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return AllocateAligned(size, align);
}

void operator delete(void* p) noexcept { Release(p); }
void operator delete[](void* p) noexcept { Release(p); }
void operator delete(void* p, std::size_t) noexcept { Release(p); }
void operator delete[](void* p, std::size_t) noexcept { Release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { Release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { Release(p); }
void operator delete(void* p, std::align_val_t) noexcept { Release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { Release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { Release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { Release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { Release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { Release(p); }
