// A parallel loop for the CPU stages (topology precomputation, CPU references): header-only, so every native
// library can use it without linking one more.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace bounce {

// Sets this thread's floating-point mode to a fixed one: round to nearest, denormals flushed to zero (FTZ, DAZ).
// A thread inherits the mode of the thread that starts it, and the one that starts the render thread is
// Blender's, in whatever mode it left: SSVP's clusters came out differently from one Blender process to another
// where tiny contributions were denormal on one thread and zero on another.
inline void use_fixed_float_mode() {
#if defined(__SSE__)
  _mm_setcsr(0x9FC0);  // all exceptions masked, round to nearest, FTZ (0x8000) and DAZ (0x0040)
#endif
}

// Calls body(i) for i in [0, count) on `threads` threads (0 or less: one per hardware thread), never more
// threads than there are grains, `grain` consecutive items at a time, handed out in order as threads come free
// (so uneven items balance), each in the caller's floating-point mode, so that which thread takes an item never
// changes its result; rethrows the first exception.
template <class Body>
void parallel_for(std::size_t count, int threads, std::size_t grain, const Body& body) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t wanted = threads > 0 ? std::size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::clamp<std::size_t>((count + grain - 1) / grain, 1, wanted);
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
#if defined(__SSE__)
  const unsigned int float_mode = _mm_getcsr();
#endif
  auto work = [&] {
#if defined(__SSE__)
    _mm_setcsr(float_mode);
#endif
    try {
      for (;;) {
        const std::size_t begin = next.fetch_add(grain);
        if (begin >= count) return;
        const std::size_t end = std::min(count, begin + grain);
        for (std::size_t i = begin; i < end; ++i) body(i);
      }
    } catch (...) {
      std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next = count;
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace bounce
