#include "schedulers/ws_deque.h"

#include "schedulers/scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

namespace hrad {
namespace {

std::vector<int> pop_all_one_by_one(WsDeque<int>& d) {
  std::vector<int> v;
  while (auto x = d.pop()) v.push_back(*x);
  return v;
}

TEST(DequeSingle, PopIsLifo) {
  WsDeque<int> d;
  for (int i = 0; i < 100; ++i) d.push(i);
  EXPECT_EQ(d.size_estimate(), 100);
  std::vector<int> expect(100);
  for (int i = 0; i < 100; ++i) expect[static_cast<std::size_t>(i)] = 99 - i;
  EXPECT_EQ(pop_all_one_by_one(d), expect);
  EXPECT_EQ(d.size_estimate(), 0);
  EXPECT_FALSE(d.pop().has_value());
}

TEST(DequeSingle, StealIsFifo) {
  WsDeque<int> d;
  for (int i = 0; i < 100; ++i) d.push(i);
  for (int i = 0; i < 100; ++i) {
    int x = -1;
    ASSERT_EQ(d.steal(x), StealResult::kSuccess);
    EXPECT_EQ(x, i);
  }
  int x = -1;
  EXPECT_EQ(d.steal(x), StealResult::kEmpty);
  EXPECT_FALSE(d.pop().has_value());
}

TEST(DequeSingle, BothEndsMeet) {
  WsDeque<int> d;
  for (int i = 0; i < 5; ++i) d.push(i);
  int x = -1;
  ASSERT_EQ(d.steal(x), StealResult::kSuccess);
  EXPECT_EQ(x, 0);
  EXPECT_EQ(d.pop(), 4);
  ASSERT_EQ(d.steal(x), StealResult::kSuccess);
  EXPECT_EQ(x, 1);
  EXPECT_EQ(d.pop(), 3);
  EXPECT_EQ(d.pop(), 2);  // the last item: the CAS path
  EXPECT_FALSE(d.pop().has_value());
  EXPECT_EQ(d.steal(x), StealResult::kEmpty);
  // Still usable after being emptied from both ends.
  d.push(7);
  EXPECT_EQ(d.size_estimate(), 1);
  EXPECT_EQ(d.pop(), 7);
}

TEST(DequeSingle, EmptyOperations) {
  WsDeque<int> d;
  EXPECT_FALSE(d.pop().has_value());
  EXPECT_EQ(d.pop(std::span<int>()), 0u);
  d.push(std::span<const int>());
  int x = 3;
  EXPECT_EQ(d.steal(x), StealResult::kEmpty);
  EXPECT_EQ(x, 3);  // untouched
  EXPECT_EQ(d.size_estimate(), 0);
  // Repeated failed pops must not drift the indices.
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(d.pop().has_value());
  d.push(1);
  d.push(2);
  EXPECT_EQ(d.size_estimate(), 2);
  EXPECT_EQ(pop_all_one_by_one(d), (std::vector<int>{2, 1}));
}

TEST(DequeSingle, BatchPopNewestFirst) {
  WsDeque<int> d;
  const std::vector<int> in = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  d.push(std::span<const int>(in));
  std::vector<int> out(4);
  ASSERT_EQ(d.pop(std::span<int>(out)), 4u);
  EXPECT_EQ(out, (std::vector<int>{9, 8, 7, 6}));
  out.assign(100, -1);
  ASSERT_EQ(d.pop(std::span<int>(out)), 6u);  // asks for more than there is
  EXPECT_EQ(std::vector<int>(out.begin(), out.begin() + 6), (std::vector<int>{5, 4, 3, 2, 1, 0}));
  EXPECT_EQ(d.pop(std::span<int>(out)), 0u);
  d.push(42);
  EXPECT_EQ(d.pop(), 42);
}

TEST(DequeSingle, BatchPopAfterSteals) {
  // top has moved: the claimed range straddles it, so the lowest item takes the CAS.
  WsDeque<int> d;
  for (int i = 0; i < 6; ++i) d.push(i);
  int x = -1;
  ASSERT_EQ(d.steal(x), StealResult::kSuccess);
  ASSERT_EQ(d.steal(x), StealResult::kSuccess);
  std::vector<int> out(8, -1);
  ASSERT_EQ(d.pop(std::span<int>(out)), 4u);
  EXPECT_EQ(std::vector<int>(out.begin(), out.begin() + 4), (std::vector<int>{5, 4, 3, 2}));
  EXPECT_EQ(d.steal(x), StealResult::kEmpty);
  // Exactly the remaining count: top == claimed start.
  for (int i = 10; i < 13; ++i) d.push(i);
  ASSERT_EQ(d.steal(x), StealResult::kSuccess);
  EXPECT_EQ(x, 10);
  ASSERT_EQ(d.pop(std::span<int>(out.data(), 2)), 2u);
  EXPECT_EQ(out[0], 12);
  EXPECT_EQ(out[1], 11);
  EXPECT_FALSE(d.pop().has_value());
}

TEST(DequeSingle, GrowsAcrossWrapAround) {
  // Capacity 2 and steals interleaved with pushes: top is never 0 when the array
  // grows, so the copy must follow the circular indices.
  WsDeque<int> d(2);
  EXPECT_EQ(d.capacity(), 2u);
  std::vector<int> stolen;
  int next_steal_expect = 0;
  for (int i = 0; i < 1000; ++i) {
    d.push(i);
    if (i % 3 == 2) {
      int x = -1;
      ASSERT_EQ(d.steal(x), StealResult::kSuccess);
      EXPECT_EQ(x, next_steal_expect++);
    }
  }
  EXPECT_GE(d.capacity(), static_cast<std::size_t>(1000 - 333));
  std::vector<int> rest = pop_all_one_by_one(d);
  ASSERT_EQ(rest.size(), 1000u - 333u);
  for (std::size_t k = 0; k < rest.size(); ++k) EXPECT_EQ(rest[k], 999 - static_cast<int>(k));
}

TEST(DequeSingle, BatchPushGrowsOnce) {
  WsDeque<int> d(2);
  std::vector<int> in(1000);
  for (int i = 0; i < 1000; ++i) in[static_cast<std::size_t>(i)] = i;
  d.push(std::span<const int>(in));
  EXPECT_EQ(d.capacity(), 1024u);
  int x = -1;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(d.steal(x), StealResult::kSuccess);
    ASSERT_EQ(x, i);
  }
}

Task make_task(std::uint64_t id) {
  Task t;
  t.receiver = std::bit_cast<Element*>(static_cast<std::uintptr_t>(id));
  t.source = std::bit_cast<Element*>(~static_cast<std::uintptr_t>(id));
  t.form_factor = static_cast<float>(id % 1000) * 0.25f;
  t.visibility = static_cast<float>(id % 7);
  t.priority = -static_cast<float>(id % 4096);
  t.evaluated = (id & 1) != 0;
  return t;
}

// Returns the id, or ~0 when the fields disagree (a torn or corrupted copy).
std::uint64_t task_id(const Task& t) {
  const auto id = static_cast<std::uint64_t>(std::bit_cast<std::uintptr_t>(t.receiver));
  const Task e = make_task(id);
  const bool same = t.source == e.source && t.form_factor == e.form_factor &&
                    t.visibility == e.visibility && t.priority == e.priority &&
                    t.evaluated == e.evaluated;
  return same ? id : ~std::uint64_t{0};
}

TEST(DequeSingle, TaskRoundTripsEveryField) {
  WsDeque<Task> d(2);
  for (std::uint64_t i = 0; i < 50; ++i) d.push(make_task(i * 977 + 3));
  Task t;
  ASSERT_EQ(d.steal(t), StealResult::kSuccess);
  EXPECT_EQ(task_id(t), 3u);
  const std::optional<Task> last = d.pop();
  ASSERT_TRUE(last.has_value());
  EXPECT_EQ(task_id(*last), 49u * 977 + 3);
}

// The classic test: one owner pushes N items (in single pushes and small batches) and
// pops (single and batched) in between, while three thieves steal; everything that came
// out, by any route, equals what went in, each item exactly once.
template <class T, class Encode, class Decode>
void owner_and_thieves(std::uint64_t n, std::uint32_t seed, Encode encode, Decode decode) {
  constexpr int kThieves = 3;
  WsDeque<T> d(2);  // small, so the array grows while thieves read it
  std::atomic<bool> start{false}, done{false};
  std::vector<std::vector<std::uint64_t>> got(kThieves + 1);
  std::vector<std::thread> thieves;
  for (int k = 0; k < kThieves; ++k) {
    thieves.emplace_back([&, k] {
      while (!start.load(std::memory_order_acquire)) std::this_thread::yield();
      std::vector<std::uint64_t>& mine = got[static_cast<std::size_t>(k + 1)];
      T item;
      while (!done.load(std::memory_order_acquire)) {
        if (d.steal(item) == StealResult::kSuccess) mine.push_back(decode(item));
      }
    });
  }
  std::mt19937 rng(seed);
  std::vector<T> batch, out(8);
  std::vector<std::uint64_t>& mine = got[0];
  start.store(true, std::memory_order_release);
  std::uint64_t next = 0;
  while (next < n) {
    const std::uint64_t m = std::min<std::uint64_t>(n - next, 1 + rng() % 4);
    batch.clear();
    for (std::uint64_t i = 0; i < m; ++i) batch.push_back(encode(next++));
    if (m == 1)
      d.push(batch[0]);
    else
      d.push(std::span<const T>(batch));
    if (rng() % 3 == 0) {
      const std::size_t want = 1 + rng() % out.size();
      const std::size_t k = d.pop(std::span<T>(out.data(), want));
      for (std::size_t i = 0; i < k; ++i) mine.push_back(decode(out[i]));
    }
  }
  // Drain: once a pop finds nothing after the last push, nothing is left for anyone.
  for (;;) {
    const std::size_t k = d.pop(std::span<T>(out));
    if (k == 0) break;
    for (std::size_t i = 0; i < k; ++i) mine.push_back(decode(out[i]));
  }
  done.store(true, std::memory_order_release);
  for (std::thread& t : thieves) t.join();

  std::vector<std::uint32_t> seen(n, 0);
  std::uint64_t total = 0;
  for (const auto& v : got) {
    for (std::uint64_t id : v) {
      ASSERT_LT(id, n) << "corrupted or torn item";
      ++seen[id];
      ++total;
    }
  }
  EXPECT_EQ(total, n);
  for (std::uint64_t id = 0; id < n; ++id) ASSERT_EQ(seen[id], 1u) << "item " << id;
  EXPECT_EQ(d.size_estimate(), 0);
}

class DequeConcurrent : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(DequeConcurrent, OwnerPopsWhileThreeThievesStealExactlyOnce) {
  const std::uint64_t n = GetParam();
  // Small N finish in microseconds: repeat them so the races at the last item happen.
  const int rounds = static_cast<int>(std::clamp<std::uint64_t>(20000 / n, 1, 100));
  for (int r = 0; r < rounds; ++r) {
    owner_and_thieves<std::uint64_t>(
        n, static_cast<std::uint32_t>(r + 1), [](std::uint64_t i) { return i; },
        [](std::uint64_t x) { return x; });
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST_P(DequeConcurrent, TasksArriveWhole) {
  const std::uint64_t n = GetParam();
  owner_and_thieves<Task>(n, 7, make_task, task_id);
}

INSTANTIATE_TEST_SUITE_P(Deque, DequeConcurrent,
                         ::testing::Values(1, 4, 13, 100, 1000, 10000, 100000));

}  // namespace
}  // namespace hrad
