// Blocks of a stream reduced on threads and consumed in block order, so that
// results depend on the blocks, never on the number of threads or on timing
// (streaming.hpp, "Determinism"). Private to the streaming identifiers.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "massid/streaming.hpp"

namespace massid::detail {

inline int thread_count(const StreamOptions& stream) {
  if (stream.threads > 0) return stream.threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

// Runs make(k) for the blocks k = 0 .. num_blocks - 1 on `threads` threads and
// hands the results to consume() one at a time in block order, so that the
// result does not depend on the number of threads or on timing. At most
// 4 * threads blocks are ahead of the one awaited (bounded memory). When a
// block throws, later blocks are skipped and, once every thread has stopped,
// the exception of the lowest failing block (the first error in the data) is
// rethrown.
template <class Partial, class Make, class Consume>
void ordered_blocks(size_t num_blocks, int threads, Make make, Consume consume) {
  if (threads <= 1 || num_blocks <= 1) {
    for (size_t k = 0; k < num_blocks; ++k) consume(make(k));
    return;
  }
  std::mutex mu;
  std::condition_variable cv;
  size_t next_claim = 0, next_consume = 0;
  size_t error_block = std::numeric_limits<size_t>::max();
  std::exception_ptr error;
  bool consuming = false;
  std::map<size_t, Partial> ready;
  const size_t ahead = 4 * static_cast<size_t>(threads);

  auto worker = [&] {
    while (true) {
      size_t k;
      {
        std::unique_lock<std::mutex> lock(mu);
        cv.wait(lock, [&] {
          return next_claim >= num_blocks || next_claim > error_block ||
                 next_claim < next_consume + ahead;
        });
        if (next_claim >= num_blocks || next_claim > error_block) return;
        k = next_claim++;
      }
      std::optional<Partial> part;
      std::exception_ptr failure;
      try {
        part.emplace(make(k));
      } catch (...) {
        failure = std::current_exception();
      }
      std::unique_lock<std::mutex> lock(mu);
      if (failure) {
        if (k < error_block) {
          error_block = k;
          error = failure;
        }
        cv.notify_all();
        continue;
      }
      ready.emplace(k, std::move(*part));
      while (!consuming && !ready.empty() && ready.begin()->first == next_consume &&
             next_consume < error_block) {
        consuming = true;
        auto node = ready.extract(ready.begin());
        lock.unlock();
        std::exception_ptr consume_failure;
        try {
          consume(std::move(node.mapped()));
        } catch (...) {
          consume_failure = std::current_exception();
        }
        lock.lock();
        consuming = false;
        if (consume_failure && next_consume < error_block) {
          error_block = next_consume;
          error = consume_failure;
        }
        ++next_consume;
      }
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace massid::detail
