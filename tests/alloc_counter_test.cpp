// The allocation counter (tests/alloc_counter.cpp) counts every replaceable form of operator
// new, and each form's memory is released by the matching delete without a mismatch (which
// AddressSanitizer reports, scripts/sanitize.sh).
#include <gtest/gtest.h>

#include <cstdint>
#include <new>

long AllocationCount();  // tests/alloc_counter.cpp

namespace {

// Keeps the compiler from eliding an allocation whose memory is never read (new-expressions
// may be elided, and GCC removes unused new/delete pairs).
template <class T>
T* Keep(T* p) {
  asm volatile("" : : "g"(p) : "memory");
  return p;
}

struct alignas(64) Wide {
  std::uint8_t bytes[64];
};

TEST(AllocCounter, CountsEveryFormOfNew) {
  const long before = AllocationCount();
  int* plain = Keep(new int(1));
  int* array = Keep(new int[3]);
  int* nothrow = Keep(new (std::nothrow) int(2));
  int* nothrow_array = Keep(new (std::nothrow) int[3]);
  Wide* aligned = Keep(new Wide);
  Wide* aligned_array = Keep(new Wide[2]);
  Wide* aligned_nothrow = Keep(new (std::nothrow) Wide);
  EXPECT_EQ(AllocationCount() - before, 7);
  ASSERT_NE(nothrow, nullptr);
  ASSERT_NE(nothrow_array, nullptr);
  ASSERT_NE(aligned_nothrow, nullptr);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned_array) % 64, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned_nothrow) % 64, 0u);
  delete plain;
  delete[] array;
  delete nothrow;
  delete[] nothrow_array;
  delete aligned;
  delete[] aligned_array;
  delete aligned_nothrow;
  ::operator delete(Keep(::operator new(8, std::nothrow)), std::nothrow);
  ::operator delete(Keep(::operator new(128, std::align_val_t(64), std::nothrow)),
                    std::align_val_t(64), std::nothrow);
  EXPECT_EQ(AllocationCount() - before, 9);
}

}  // namespace
