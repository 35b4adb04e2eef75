// Where a stage's TBB loops run. With a thread count (backend.threads > 0) the stage keeps a
// task_arena of that width, so that the engine uses that many cores whoever calls it. With 0
// it runs its loops in the caller's arena, as every other TBB loop of the engine does: the TBB
// workers then stay in one arena for the whole scan instead of moving from one arena to the
// next between stages, which on two cores cost the stage after such a move about 20 us a scan.
#pragma once

#include <tbb/task_arena.h>

#include <memory>
#include <utility>

namespace freespace {

class ThreadArena {
 public:
  explicit ThreadArena(int threads)
      : own_(threads > 0 ? std::make_unique<tbb::task_arena>(threads) : nullptr) {
    if (own_) own_->initialize();
  }

  template <typename F>
  void execute(F&& f) {
    if (own_) {
      own_->execute(std::forward<F>(f));
    } else {
      f();
    }
  }

 private:
  std::unique_ptr<tbb::task_arena> own_;
};

}  // namespace freespace
