// ChunkStack: a LIFO of task chunks, one chunk per submitted batch, with recycled
// buffers: the pool shape of the paper's blocked scheduler (§3.5), without the lock.
// The caller holds its own lock around push() and pop(); the expensive parts (copying
// a batch into a buffer, freeing an oversized one) happen outside it:
//  - push() moves a filled buffer onto the stack in O(1) and hands back an empty
//    recycled buffer (or an empty vector) for the caller's next batch;
//  - pop() copies out up to `want` tasks, newest first (a take may span chunks), in
//    O(want); an emptied buffer is kept for reuse, or handed to `discard` to be freed
//    by the caller after unlocking when it is oversized or the spare list is full.
// Order: LIFO over chunks and newest first inside a chunk, exactly `stack`'s order;
// pop_oldest() takes from the bottom chunk instead (for a thief: the oldest work is
// the largest, and the least recently touched by its owner).
// Used by `blocked` (one per refiner, under one lock) and `locality` (one per NUMA node).
#pragma once

#include "schedulers/scheduler.h"

#include <algorithm>
#include <cstddef>
#include <deque>
#include <span>
#include <utility>
#include <vector>

namespace hrad {

class ChunkStack {
 public:
  /// Buffers bigger than this (in tasks) are freed rather than recycled, so a huge
  /// initial batch does not stay allocated; at most kMaxSpares buffers wait for reuse.
  static constexpr std::size_t kMaxRecycledCapacity = std::size_t{1} << 14;
  static constexpr std::size_t kMaxSpares = 64;

  ChunkStack() { spares_.reserve(kMaxSpares); }

  [[nodiscard]] bool empty() const { return chunks_.empty(); }
  [[nodiscard]] std::size_t size() const { return size_; }  ///< tasks held

  /// Moves `chunk` (non-empty) onto the stack; `chunk` becomes a recycled empty buffer.
  void push(std::vector<Task>& chunk) {
    size_ += chunk.size();
    chunks_.push_back(std::move(chunk));
    chunk = std::vector<Task>();
    if (!spares_.empty()) {
      chunk = std::move(spares_.back());
      spares_.pop_back();
    }
  }

  /// Copies up to `want` tasks (newest first) into out[0..); returns how many.
  std::size_t pop(std::span<Task> out, std::size_t want, std::vector<Task>& discard) {
    return pop_from(out, want, discard, false);
  }
  /// The same from the bottom chunk up (newest first inside each chunk).
  std::size_t pop_oldest(std::span<Task> out, std::size_t want, std::vector<Task>& discard) {
    return pop_from(out, want, discard, true);
  }

 private:
  std::size_t pop_from(std::span<Task> out, std::size_t want, std::vector<Task>& discard,
                       bool oldest) {
    want = std::min(want, out.size());
    std::size_t n = 0;
    while (n < want && !chunks_.empty()) {
      std::vector<Task>& top = oldest ? chunks_.front() : chunks_.back();
      const std::size_t k = std::min(want - n, top.size());
      std::reverse_copy(top.end() - static_cast<std::ptrdiff_t>(k), top.end(),
                        out.begin() + static_cast<std::ptrdiff_t>(n));
      top.resize(top.size() - k);  // Task is trivially destructible: O(1)
      n += k;
      if (top.empty()) {
        if (top.capacity() <= kMaxRecycledCapacity && spares_.size() < kMaxSpares)
          spares_.push_back(std::move(top));
        else
          discard.swap(top);  // a previous discard, if any, is freed here (rare)
        if (oldest)
          chunks_.pop_front();
        else
          chunks_.pop_back();
      }
    }
    size_ -= n;
    return n;
  }

  std::deque<std::vector<Task>> chunks_;   // back() is the top
  std::vector<std::vector<Task>> spares_;  // empty, capacity kept
  std::size_t size_ = 0;
};

}  // namespace hrad
