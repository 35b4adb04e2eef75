// The test binary's counting operator new (tests/alloc_counter.cpp): calls, and the heap bytes
// live and their peak (as malloc_usable_size counts them: operator new's blocks only, not
// malloc's called directly).
#pragma once

long AllocationCount();     // operator new calls so far
long LiveHeapBytes();       // bytes of operator new's blocks not yet deleted
long PeakHeapBytes();       // the most LiveHeapBytes() has been since the last reset
void ResetPeakHeapBytes();  // peak := live now
