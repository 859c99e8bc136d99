// OpenMP helpers shared by the BEM assembly and the H-matrices: the calling
// thread's number, and the guard that keeps exceptions inside parallel
// regions and tasks.
#pragma once

#include <atomic>
#include <exception>
#include <mutex>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bemcontact {

// The calling thread's number in its OpenMP team (0 without OpenMP): the
// index of its thread-private accumulators.
inline int thread_num() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// An exception that leaves an OpenMP parallel region or task calls
// std::terminate: the process aborts without a word (a std::bad_alloc in an
// H-LU task did, measured). Each piece of work runs through run(), which keeps
// the first exception and lets the team reach its barriers; after the region,
// rethrow() raises it in the calling thread (to Python as the same error:
// std::bad_alloc becomes MemoryError). Later work is skipped once one failed.
class ExceptionGuard {
 public:
  template <class F>
  void run(F&& work) noexcept {
    if (failed()) return;
    try {
      std::forward<F>(work)();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!first_) first_ = std::current_exception();
      failed_.store(true, std::memory_order_relaxed);
    }
  }
  bool failed() const { return failed_.load(std::memory_order_relaxed); }
  void rethrow() const {
    std::exception_ptr e;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      e = first_;
    }
    if (e) std::rethrow_exception(e);
  }

 private:
  mutable std::mutex mutex_;
  std::exception_ptr first_;
  std::atomic<bool> failed_{false};
};

}  // namespace bemcontact
