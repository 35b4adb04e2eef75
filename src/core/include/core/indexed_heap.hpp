// A binary heap of small integer ids that knows where each id sits, so that an id whose key
// changed moves in place and one can be taken out from anywhere. The keys stay with the caller:
// every call that moves ids takes `before(a, b)`, true when id a belongs above id b (a strict
// order). The paper polygon's simplifier keeps its segments in one (core/simplifier.hpp); the
// least-area one keeps its costs in a tournament tree (core/min_tree.hpp).
#pragma once

#include <cstddef>
#include <vector>

namespace freespace {

class IndexedHeap {
 public:
  // Ids 0 .. capacity - 1; all memory is allocated here.
  explicit IndexedHeap(int capacity)
      : heap_(std::size_t(capacity)), slot_(std::size_t(capacity), -1) {}

  bool empty() const { return size_ == 0; }
  int top() const { return heap_[0]; }
  bool contains(int id) const { return slot_[std::size_t(id)] >= 0; }

  // Takes every id out.
  void Clear() {
    for (int at = 0; at < size_; ++at) slot_[std::size_t(heap_[std::size_t(at)])] = -1;
    size_ = 0;
  }
  // Ids 0 .. n - 1 and no other, ordered at once; n at most the capacity.
  template <class Before>
  void Fill(int n, const Before& before) {
    Clear();
    for (int id = 0; id < n; ++id) Place(id, id);
    size_ = n;
    for (int at = n / 2 - 1; at >= 0; --at) SiftDown(at, before);
  }
  template <class Before>
  void Push(int id, const Before& before) {
    Place(size_++, id);
    SiftUp(size_ - 1, before);
  }
  // Id's key changed: moves it where it now belongs.
  template <class Before>
  void Update(int id, const Before& before) {
    SiftUp(slot_[std::size_t(id)], before);
    SiftDown(slot_[std::size_t(id)], before);
  }
  template <class Before>
  void Remove(int id, const Before& before) {
    const int at = slot_[std::size_t(id)];
    slot_[std::size_t(id)] = -1;
    const int last = heap_[std::size_t(--size_)];
    if (last == id) return;
    Place(at, last);
    Update(last, before);
  }

 private:
  void Place(int at, int id) {
    heap_[std::size_t(at)] = id;
    slot_[std::size_t(id)] = at;
  }
  template <class Before>
  void SiftUp(int at, const Before& before) {
    const int id = heap_[std::size_t(at)];
    while (at > 0) {
      const int parent = (at - 1) / 2;
      if (!before(id, heap_[std::size_t(parent)])) break;
      Place(at, heap_[std::size_t(parent)]);
      at = parent;
    }
    Place(at, id);
  }
  template <class Before>
  void SiftDown(int at, const Before& before) {
    const int id = heap_[std::size_t(at)];
    for (;;) {
      int child = 2 * at + 1;
      if (child >= size_) break;
      if (child + 1 < size_ && before(heap_[std::size_t(child + 1)], heap_[std::size_t(child)]))
        ++child;
      if (!before(heap_[std::size_t(child)], id)) break;
      Place(at, heap_[std::size_t(child)]);
      at = child;
    }
    Place(at, id);
  }

  std::vector<int> heap_;  // the ids in heap order, size_ of them
  std::vector<int> slot_;  // per id: its place in heap_, -1 when not there
  int size_ = 0;
};

}  // namespace freespace
