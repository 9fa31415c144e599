// `stealing`: per-worker work-stealing queues, after Singh, Gupta & Levoy (1994) and the
// SPLASH-2 radiosity code: the tasks a refiner creates stay in its own queue, and a
// refiner whose queue is empty steals from another's.
//
// | parameter  | type | default | meaning                                              |
// |------------|------|---------|------------------------------------------------------|
// | threads    | int  | 1       | workers; one WsDeque (ws_deque.h) each               |
// | block_size | int  | 0       | at most this many tasks per take(), popped or stolen;|
// |            |      |         | 0: guided (half the deque, at most kGuidedMaxBlock)  |
// | victims    | int  | 0       | its own parameter (scheduler.stealing.victims): other |
// |            |      |         | workers a thief looks at per steal, 0 = all of them   |
//
// take(w) looks, in order, at:
//  1. w's own deque: up to block_size tasks, newest first (depth-first, like the
//     recursion), one seq_cst fence per block;
//  2. the inbox (below): up to block_size tasks, newest first;
//  3. the other deques: victims scanned round-robin from a start drawn by w's own
//     deterministic generator (at most `victims` of them, when that is set); from the first non-empty victim it steals its *oldest*
//     tasks (the largest pending subtrees), one CAS each, up to min(block_size, half the
//     victim's tasks rounded up). Every stolen task counts in SchedulerCounters::steals.
//
// Who is worker w. The thread that calls take(w) acts as worker w: it claims `owner`
// (a CAS from no thread to its id) on entry and clears it when take() returns nothing
// (going idle). submit(w, tasks) pushes onto w's deque when the calling thread is w's
// recorded owner, or when no thread is (then the caller claims w for the push and gives
// it up after: this is how a refiner that found nothing loads a chunk of initial tasks
// into its own deque, and its next take claims w again); from any other thread (one
// submitting as w while another acts as w) the tasks go to the *inbox*, a shared vector
// under a mutex that any worker drains in step 2. A take that finds w claimed by another
// thread's push skips w's deque that time.
// take_own(w) is steps 1 and 2 without stealing.
//
// Precondition (what makes deque ownership sound): at most one thread acts as worker w at
// a time, and a thread hands worker w over to another only through happens-before (an
// OpenMP team gives this: worker w is thread w of the team, regions end in a barrier).
// A thread that stops acting as w without an empty take must not submit as w while
// another thread takes as w.
//
// Lock waits: takes never wait (the inbox is only try_lock'ed); only submits from a
// non-owner thread can wait for the inbox lock (timed_lock, as the central schedulers:
// a short spin, then sleep), and those waits are what lock_wait_s reports (normally 0).
#include "core/parallel/timed_lock.h"
#include "schedulers/scheduler.h"
#include "schedulers/ws_deque.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

namespace hrad {
namespace {

// A counter written by one thread at a time (the worker's), read by counters() from any:
// relaxed load and store, no read-modify-write needed.
class OwnerCounter {
 public:
  void add(std::uint64_t n) {
    v_.store(v_.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t get() const { return v_.load(std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> v_{0};
};

struct alignas(64) Worker {
  WsDeque<Task> deque;
  // The thread currently acting as this worker (default id: none). Written relaxed by
  // that thread; other threads only compare it with their own id, which it can equal
  // only if they wrote it themselves. It and the fields below, all written by the owner,
  // get their own cache line, away from the deque's lines that thieves read.
  alignas(64) std::atomic<std::thread::id> owner{};
  std::uint64_t rng = 0;  // victim choice; touched by the owner only
  OwnerCounter takes, empty_takes, submits, steals;
};

class StealingScheduler final : public IScheduler {
 public:
  StealingScheduler(const SchedulerConfig& config, int victims)
      : threads_(config.threads),
        block_size_(static_cast<std::size_t>(config.block_size)),
        victims_(victims > 0 ? std::min(victims, config.threads - 1) : config.threads - 1),
        workers_(new Worker[static_cast<std::size_t>(config.threads)]) {
    for (int w = 0; w < threads_; ++w)
      at(w).rng = 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(w + 1);  // never 0
  }

  std::size_t take(int worker, std::span<Task> out) override {
    return take_from(worker, out, true);
  }
  std::size_t take_own(int worker, std::span<Task> out) override {
    return take_from(worker, out, false);
  }

  void submit(int worker, std::span<const Task> tasks) override {
    if (tasks.empty()) return;
    Worker& w = at(worker);
    const std::thread::id self = std::this_thread::get_id();
    std::thread::id owner = w.owner.load(std::memory_order_acquire);
    // No thread acts as w (its last take was empty): the caller acts as w for this
    // push, claiming it with a CAS so that a take of the team's thread w cannot pop
    // while it pushes, and gives w up after it (a refiner that loaded its own chunk
    // claims w again with its next take). With a plain store here, a thread outside the
    // team and the team's thread w could both act on w's deque at once, and a task was
    // lost (SchedForeign's stealing case hung 1 run in 3).
    bool claimed = false;
    if (owner == std::thread::id()) {
      claimed = w.owner.compare_exchange_strong(owner, self, std::memory_order_acq_rel);
      if (claimed) owner = self;
    }
    if (owner == self) {
      w.deque.push(tasks);
      w.submits.add(1);
      if (claimed) w.owner.store(std::thread::id(), std::memory_order_release);
      return;
    }
    const std::unique_lock lock = timed_lock(inbox_mutex_, inbox_wait_s_);
    inbox_.insert(inbox_.end(), tasks.begin(), tasks.end());
    ++inbox_submits_;
    inbox_size_.store(inbox_.size(), std::memory_order_relaxed);
  }

  [[nodiscard]] SchedulerCounters counters() const override {
    SchedulerCounters c;
    for (int w = 0; w < threads_; ++w) {
      const Worker& x = workers_[static_cast<std::size_t>(w)];
      c.takes += x.takes.get();
      c.empty_takes += x.empty_takes.get();
      c.submits += x.submits.get();
      c.steals += x.steals.get();
    }
    std::lock_guard lock(inbox_mutex_);
    c.submits += inbox_submits_;
    c.lock_wait_s = inbox_wait_s_;
    return c;
  }

  [[nodiscard]] const char* name() const override { return "stealing"; }

 private:
  std::size_t take_from(int worker, std::span<Task> out, bool may_steal) {
    Worker& me = at(worker);
    const std::thread::id self = std::this_thread::get_id();
    // The caller acts as w when it already does or no thread does; while a submit from
    // another thread holds w for its push, w's own deque is left to it this time.
    std::thread::id owner = me.owner.load(std::memory_order_acquire);
    const bool mine =
        owner == self || (owner == std::thread::id() &&
                          me.owner.compare_exchange_strong(owner, self, std::memory_order_acq_rel));
    // Guided (block_size 0): the owner pops half its deque, at most kGuidedMaxBlock
    // (guided_block with one thread's share), leaving the rest to thieves; a thief
    // takes half the victim's (steal()).
    const std::size_t own =
        block_size_ > 0 ? block_size_
                        : guided_block(static_cast<std::size_t>(me.deque.size_estimate()), 1);
    const std::span<Task> block =
        out.first(std::min(out.size(), block_size_ > 0 ? block_size_ : kGuidedMaxBlock));
    std::size_t n = mine ? me.deque.pop(block.first(std::min(block.size(), own))) : 0;
    if (n == 0) n = take_from_inbox(block);
    if (n == 0 && may_steal) {
      n = steal(worker, me, block);
      me.steals.add(n);
    }
    if (n > 0) {
      me.takes.add(1);
    } else {
      me.empty_takes.add(1);
      if (mine) me.owner.store(std::thread::id(), std::memory_order_release);  // idle: give up w
    }
    return n;
  }

  Worker& at(int worker) { return workers_[static_cast<std::size_t>(worker)]; }

  // Up to out.size() tasks from the inbox, newest first. Never waits: a busy inbox is
  // skipped and the caller moves on to stealing (or comes back on its next take).
  // inbox_size_ is only a hint that spares the lock when the inbox is empty; the mutex
  // orders the task data.
  std::size_t take_from_inbox(std::span<Task> out) {
    if (out.empty() || inbox_size_.load(std::memory_order_relaxed) == 0) return 0;
    std::unique_lock lock(inbox_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return 0;
    const std::size_t n = std::min(out.size(), inbox_.size());
    std::reverse_copy(inbox_.end() - static_cast<std::ptrdiff_t>(n), inbox_.end(), out.begin());
    inbox_.resize(inbox_.size() - n);
    inbox_size_.store(inbox_.size(), std::memory_order_relaxed);
    return n;
  }

  // Steals into `out` from the first victim that has tasks; returns how many.
  std::size_t steal(int self, Worker& me, std::span<Task> out) {
    if (threads_ == 1 || out.empty()) return 0;
    // xorshift64: deterministic per worker, cheap, good enough to spread victims.
    me.rng ^= me.rng << 13;
    me.rng ^= me.rng >> 7;
    me.rng ^= me.rng << 17;
    const int others = threads_ - 1;
    const int start = static_cast<int>(me.rng % static_cast<std::uint64_t>(others));
    for (int i = 0; i < victims_; ++i) {
      int victim = (start + i) % others;
      if (victim >= self) ++victim;  // skip self: victims are 0..threads-1 minus self
      WsDeque<Task>& d = at(victim).deque;
      const std::int64_t avail = d.size_estimate();
      if (avail == 0) continue;
      const std::size_t quota = std::min(out.size(), static_cast<std::size_t>((avail + 1) / 2));
      std::size_t got = 0;
      while (got < quota && d.steal(out[got]) == StealResult::kSuccess) ++got;
      // An abort means another worker just took from this victim: that is progress, so
      // moving on (or returning what we have) keeps the scheduler lock-free.
      if (got > 0) return got;
    }
    return 0;
  }

  const int threads_;
  const std::size_t block_size_;
  const int victims_;  // other workers looked at per steal (1 .. threads_ - 1)
  std::unique_ptr<Worker[]> workers_;

  mutable std::mutex inbox_mutex_;
  std::vector<Task> inbox_;          // guarded by inbox_mutex_
  std::uint64_t inbox_submits_ = 0;  // guarded by inbox_mutex_
  double inbox_wait_s_ = 0;          // guarded by inbox_mutex_
  std::atomic<std::size_t> inbox_size_{0};
};

const bool registered = register_scheduler(
    "stealing",
    [](const SchedulerConfig& c, const PluginParams& p) {
      return std::make_unique<StealingScheduler>(c, p.get_int("victims"));
    },
    {{"victims", ParamSpec::Type::Int, 0, 0, 4096,
      "other refiners a thief looks at per steal, from a random start (0: all of them)"}});

}  // namespace
}  // namespace hrad
