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

#include "massid/identify/streaming.hpp"

namespace massid::detail {

inline int thread_count(const StreamOptions& stream) {
  if (stream.threads > 0) return stream.threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

// Runs parse(k) for blocks k = 0 .. n - 1 on `threads` threads, sequence(P&)
// on each parsed block in block order (one at a time), work(P&&) -> W on the
// threads, and merge(W&&) in block order: the result does not depend on the
// number of threads or on timing. At most 2 threads + 2 blocks past the next
// one to merge are parsed (bounded memory). When a stage throws for block k,
// later blocks are skipped, earlier ones finish, and the exception of the
// lowest failing block (the first error in the data) is rethrown once every
// thread has stopped.
template <class P, class W, class Parse, class Sequence, class Work, class Merge>
void ordered_pipeline(size_t n, int threads, Parse parse, Sequence sequence, Work work,
                      Merge merge) {
  if (threads <= 1 || n <= 1) {
    for (size_t k = 0; k < n; ++k) {
      P p = parse(k);
      sequence(p);
      merge(work(std::move(p)));
    }
    return;
  }
  using Lock = std::unique_lock<std::mutex>;
  std::mutex mu;
  std::condition_variable cv;
  size_t next_parse = 0, next_sequence = 0, next_merge = 0;
  size_t error_block = std::numeric_limits<size_t>::max();
  std::exception_ptr error;
  std::map<size_t, P> parsed, ready;  // ready: sequenced, waiting for work
  std::map<size_t, W> worked;
  bool sequencing = false, merging = false;
  int busy = 0;
  const size_t ahead = 2 * static_cast<size_t>(threads) + 2;
  const auto fail = [&](size_t k, std::exception_ptr e) {
    if (k < error_block) {
      error_block = k;
      error = std::move(e);
    }
  };
  // f() with the lock released; what it threw, if anything.
  const auto unlocked = [](Lock& lock, auto&& f) {
    lock.unlock();
    std::exception_ptr e;
    try {
      f();
    } catch (...) {
      e = std::current_exception();
    }
    lock.lock();
    return e;
  };
  // An in-order stage: stage(T&) on the entries of `done` that are next in
  // block order, by one thread at a time; then(node) for those that succeed.
  const auto in_order = [&](Lock& lock, auto& done, size_t& next, bool& running, auto&& stage,
                            auto&& then) {
    while (!running && !done.empty() && done.begin()->first == next && next < error_block) {
      running = true;
      auto node = done.extract(done.begin());
      std::exception_ptr e = unlocked(lock, [&] { stage(node.mapped()); });
      running = false;
      if (e)
        fail(next, e);
      else
        then(std::move(node));
      ++next;
    }
  };
  auto worker = [&] {
    Lock lock(mu);
    while (true) {
      if (!ready.empty() && ready.begin()->first < error_block) {
        auto node = ready.extract(ready.begin());
        const size_t k = node.key();
        ++busy;
        std::optional<W> w;
        if (auto e = unlocked(lock, [&] { w.emplace(work(std::move(node.mapped()))); }))
          fail(k, e);
        else
          worked.emplace(k, std::move(*w));
        in_order(
            lock, worked, next_merge, merging, [&](W& m) { merge(std::move(m)); }, [](auto&&) {});
      } else if (next_parse < n && next_parse < error_block && next_parse < next_merge + ahead) {
        const size_t k = next_parse++;
        ++busy;
        std::optional<P> p;
        if (auto e = unlocked(lock, [&] { p.emplace(parse(k)); }))
          fail(k, e);
        else
          parsed.emplace(k, std::move(*p));
        in_order(
            lock, parsed, next_sequence, sequencing, [&](P& b) { sequence(b); },
            [&](auto&& node) { ready.insert(std::move(node)); });
      } else if (busy == 0) {
        cv.notify_all();
        return;
      } else {
        cv.wait(lock);
        continue;
      }
      --busy;
      cv.notify_all();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Runs make(k) for the blocks k = 0 .. num_blocks - 1 on `threads` threads and
// hands the results to consume() one at a time in block order: the pipeline
// above without its sequencing stage.
template <class Partial, class Make, class Consume>
void ordered_blocks(size_t num_blocks, int threads, Make make, Consume consume) {
  ordered_pipeline<Partial, Partial>(
      num_blocks, threads, make, [](Partial&) {}, [](Partial&& p) { return std::move(p); },
      consume);
}

}  // namespace massid::detail
