// WsDeque<T>: a Chase–Lev work-stealing deque (Chase & Lev, SPAA 2005) with the C11
// memory orderings proved correct by Lê, Pop, Cohen & Zappa Nardelli (PPoPP 2013).
//
// | parameter        | type        | default | meaning                                    |
// |------------------|-------------|---------|--------------------------------------------|
// | T                | type        | –       | item, trivially copyable (hrad uses Task)  |
// | initial_capacity | std::size_t | 64      | slots before the first growth (power of 2) |
//
// One *owner* pushes and pops at the bottom (LIFO); any number of *thieves* steal one
// item at a time from the top (FIFO) with a CAS on `top_`. The deque knows nothing about
// threads: "owner" is whoever calls push/pop, and the caller guarantees that owner calls
// never overlap and are ordered by happens-before (one thread, or ownership handed over
// through a lock or a barrier). steal() and size_estimate() may be called by anyone.
//
// Invariants. Items live at indices [top_, bottom_) of a circular array whose capacity is
// a power of two (slot = index & mask). Indices are int64 and only grow, so they never
// wrap. top_ only increases (CAS by thieves, or by the owner for the last item); bottom_
// is written by the owner only. The array only grows (doubling when full); an array
// replaced by a bigger one is *retired*, not freed: a thief that loaded the old pointer may
// still read it, and since the owner never writes a retired array its slots keep their
// values. Retired arrays are freed by the destructor (their total size is below the live
// array's, so memory stays under twice the peak).
//
// Slots are atomic words. A thief holding a stale `top` may read a slot while the owner
// overwrites it after wrapping around; its CAS then fails and the (possibly torn) value
// is discarded. Plain T slots would make that a data race, so each slot is an array of
// std::atomic<uint64_t> accessed relaxed, and T is copied in and out with memcpy.
//
// Memory orderings (Lê et al. Fig. 1, with one deliberate strengthening):
//  - push: slot stores relaxed, then bottom_.store(release). Lê et al. write a release
//    fence followed by a relaxed store; we make *every* owner store of bottom_ a release
//    store instead (free on x86, one stlr on ARM). A thief's acquire load of bottom_ then
//    synchronizes with whichever owner store it reads, including the stores in pop(), so
//    every slot write sequenced before it is visible. ThreadSanitizer does not model
//    stand-alone fences; with release stores it sees the publication edge directly.
//  - pop: bottom_ lowered, then a seq_cst fence, then top_ read relaxed. The fence pairs
//    with the thief's seq_cst fence between its top_ and bottom_ loads: either the owner
//    sees the thief's CAS on top_ or the thief sees the lowered bottom_ (store-load order,
//    which no acquire/release pairing gives). Contention for the last claimed item is
//    settled by a seq_cst CAS on top_.
//  - steal: top_ acquire, seq_cst fence, bottom_ acquire, array_ acquire (Lê et al.
//    use consume, which compilers promote to acquire), slot relaxed, CAS top_ seq_cst.
//  - push reads top_ with acquire: a thief's successful CAS (a release) happens before
//    the owner reuses that thief's slot, so the thief's slot read never sees the reuse.
//  - growth: the copy into the new array is published by array_.store(release); thieves
//    load array_ after bottom_, so a thief that saw an index pushed after the growth also
//    sees the new array.
//
// Batched pop (an extension of the paper's take, same proof shape): the owner lowers
// bottom_ by k at once, claiming [B-k, B). Only the lowest claimed index that a thief
// could also reach needs the CAS: if top < B-k no thief can reach the claimed range; if
// B-k <= top < B the items above top are the owner's and the item at top is contended.
// Stealing stays one item per CAS (a batched steal needs a different protocol).
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

namespace hrad {

enum class StealResult {
  kSuccess,  ///< an item was taken
  kEmpty,    ///< the deque looked empty
  kAbort,    ///< lost a race with another thief or the owner; the deque may not be empty
};

template <class T>
class WsDeque {
  static_assert(std::is_trivially_copyable_v<T>, "slots copy T with memcpy");
  static_assert(std::is_default_constructible_v<T>);

 public:
  explicit WsDeque(std::size_t initial_capacity = 64) {
    std::size_t cap = 2;
    while (cap < initial_capacity) cap *= 2;
    array_.store(new Array(cap), std::memory_order_relaxed);
  }
  ~WsDeque() { delete array_.load(std::memory_order_relaxed); }
  WsDeque(const WsDeque&) = delete;
  WsDeque& operator=(const WsDeque&) = delete;

  /// Owner: adds one item at the bottom.
  void push(const T& item) { push(std::span<const T>(&item, 1)); }

  /// Owner: adds `items` at the bottom in order (the last one is popped first), published
  /// to thieves by one release store.
  void push(std::span<const T> items) {
    if (items.empty()) return;
    const std::int64_t b = bottom_.load(std::memory_order_relaxed);
    const std::int64_t t = top_.load(std::memory_order_acquire);
    const auto n = static_cast<std::int64_t>(items.size());
    Array* a = array_.load(std::memory_order_relaxed);
    if (b - t + n > a->capacity()) a = grow(a, t, b, b - t + n);
    for (std::int64_t i = 0; i < n; ++i) a->put(b + i, items[static_cast<std::size_t>(i)]);
    bottom_.store(b + n, std::memory_order_release);
  }

  /// Owner: removes up to out.size() items from the bottom, newest first; returns how
  /// many. One seq_cst fence per call, whatever the count.
  std::size_t pop(std::span<T> out) {
    if (out.empty()) return 0;
    const std::int64_t old_b = bottom_.load(std::memory_order_relaxed);
    Array* a = array_.load(std::memory_order_relaxed);
    const std::int64_t b = old_b - static_cast<std::int64_t>(out.size());  // claim [b, old_b)
    bottom_.store(b, std::memory_order_release);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    std::int64_t t = top_.load(std::memory_order_relaxed);
    std::size_t n = 0;
    if (t < b) {  // no thief can reach [b, old_b): all ours, no CAS
      for (std::int64_t i = old_b - 1; i >= b; --i) a->get(i, out[n++]);
      return n;
    }
    if (t >= old_b) {  // empty: undo the claim
      bottom_.store(old_b, std::memory_order_release);
      return 0;
    }
    // b <= t < old_b: (t, old_b) are ours; index t is contended with thieves.
    for (std::int64_t i = old_b - 1; i > t; --i) a->get(i, out[n++]);
    a->get(t, out[n]);                 // kept only if the CAS wins
    const std::int64_t contended = t;  // a failed CAS overwrites t
    if (top_.compare_exchange_strong(t, contended + 1, std::memory_order_seq_cst,
                                     std::memory_order_relaxed))
      ++n;
    // top_ is now contended + 1 whoever won; the deque is empty.
    bottom_.store(contended + 1, std::memory_order_release);
    return n;
  }

  /// Owner: removes the newest item, if any.
  std::optional<T> pop() {
    T item;
    if (pop(std::span<T>(&item, 1)) == 0) return std::nullopt;
    return item;
  }

  /// Anyone: tries to take the oldest item into `out` (which holds garbage unless the
  /// result is kSuccess).
  StealResult steal(T& out) {
    std::int64_t t = top_.load(std::memory_order_acquire);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    const std::int64_t b = bottom_.load(std::memory_order_acquire);
    if (t >= b) return StealResult::kEmpty;
    const Array* a = array_.load(std::memory_order_acquire);
    a->get(t, out);
    if (!top_.compare_exchange_strong(t, t + 1, std::memory_order_seq_cst,
                                      std::memory_order_relaxed))
      return StealResult::kAbort;
    return StealResult::kSuccess;
  }

  /// Anyone: bottom - top at some recent moment (exact when quiescent; a hint otherwise).
  [[nodiscard]] std::int64_t size_estimate() const {
    const std::int64_t b = bottom_.load(std::memory_order_relaxed);
    const std::int64_t t = top_.load(std::memory_order_relaxed);
    return b > t ? b - t : 0;
  }

  /// Owner: slots in the live array.
  [[nodiscard]] std::size_t capacity() const {
    return static_cast<std::size_t>(array_.load(std::memory_order_relaxed)->capacity());
  }

 private:
  static constexpr std::size_t kFullWords = sizeof(T) / 8;
  static constexpr std::size_t kTailBytes = sizeof(T) % 8;
  static constexpr std::size_t kWords = kFullWords + (kTailBytes > 0 ? 1 : 0);
  using Slot = std::atomic<std::uint64_t>[kWords];

  class Array {
   public:
    explicit Array(std::size_t capacity)
        : mask_(static_cast<std::int64_t>(capacity) - 1), slots_(new Slot[capacity]) {}
    [[nodiscard]] std::int64_t capacity() const { return mask_ + 1; }
    // Word by word straight between the slot and the item's bytes: staging the words in
    // a local array and copying that as a whole costs a store-forwarding stall per item.
    void put(std::int64_t i, const T& item) {
      Slot& s = slots_[static_cast<std::size_t>(i & mask_)];
      const auto* src = reinterpret_cast<const unsigned char*>(&item);
      for (std::size_t k = 0; k < kFullWords; ++k) {
        std::uint64_t w;
        std::memcpy(&w, src + 8 * k, 8);
        s[k].store(w, std::memory_order_relaxed);
      }
      if constexpr (kTailBytes > 0) {
        std::uint64_t w = 0;
        std::memcpy(&w, src + 8 * kFullWords, kTailBytes);
        s[kFullWords].store(w, std::memory_order_relaxed);
      }
    }
    void get(std::int64_t i, T& item) const {
      const Slot& s = slots_[static_cast<std::size_t>(i & mask_)];
      auto* dst = reinterpret_cast<unsigned char*>(&item);
      for (std::size_t k = 0; k < kFullWords; ++k) {
        const std::uint64_t w = s[k].load(std::memory_order_relaxed);
        std::memcpy(dst + 8 * k, &w, 8);
      }
      if constexpr (kTailBytes > 0) {
        const std::uint64_t w = s[kFullWords].load(std::memory_order_relaxed);
        std::memcpy(dst + 8 * kFullWords, &w, kTailBytes);
      }
    }

   private:
    std::int64_t mask_;
    std::unique_ptr<Slot[]> slots_;
  };

  // Owner: replaces `a` by an array holding at least `needed` items, copying [t, b).
  // Indices below the current top may be copied too; they are never read again.
  Array* grow(Array* a, std::int64_t t, std::int64_t b, std::int64_t needed) {
    std::int64_t cap = a->capacity();
    while (cap < needed) cap *= 2;
    auto bigger = std::make_unique<Array>(static_cast<std::size_t>(cap));
    T item;
    for (std::int64_t i = t; i < b; ++i) {
      a->get(i, item);
      bigger->put(i, item);
    }
    retired_.emplace_back(a);
    Array* fresh = bigger.release();
    array_.store(fresh, std::memory_order_release);
    return fresh;
  }

  // top_ is written by thieves, bottom_ by the owner: separate cache lines. array_ is
  // read by everyone and written rarely.
  alignas(64) std::atomic<std::int64_t> top_{0};
  alignas(64) std::atomic<std::int64_t> bottom_{0};
  alignas(64) std::atomic<Array*> array_{nullptr};
  std::vector<std::unique_ptr<Array>> retired_;  // owner only
};

}  // namespace hrad
