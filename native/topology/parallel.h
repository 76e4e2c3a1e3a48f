// Splits [0, count) into one contiguous range per hardware thread and runs body(begin, end) on each.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace bounce::topology {

template <typename Body>
void parallel_for(size_t count, Body&& body, size_t min_per_thread = 64) {
  const size_t threads = std::clamp<size_t>(count / std::max<size_t>(min_per_thread, 1), 1,
                                            std::max(1u, std::thread::hardware_concurrency()));
  if (threads == 1) {
    body(size_t(0), count);
    return;
  }
  std::vector<std::jthread> workers;
  workers.reserve(threads - 1);
  const size_t step = (count + threads - 1) / threads;
  for (size_t t = 1; t < threads; ++t) {
    const size_t begin = std::min(count, t * step), end = std::min(count, begin + step);
    workers.emplace_back([&body, begin, end] { body(begin, end); });
  }
  body(size_t(0), std::min(count, step));
}

}  // namespace bounce::topology
