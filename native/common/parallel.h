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

namespace bounce {

// Calls body(i) for i in [0, count) on `threads` threads (0 or less: one per hardware thread), never more
// threads than there are grains, `grain` consecutive items at a time, handed out in order as threads come free
// (so uneven items balance); rethrows the first exception.
template <class Body>
void parallel_for(std::size_t count, int threads, std::size_t grain, const Body& body) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t wanted = threads > 0 ? std::size_t(threads) : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers = std::clamp<std::size_t>((count + grain - 1) / grain, 1, wanted);
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
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
