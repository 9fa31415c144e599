// The simulator's contention model and guided blocks (experiments/sim/) on hand-made
// traces with analytic answers: a saturated central lock passes once per hold +
// handoff_ns + (T − 2) × handoff_waiter_ns; a lock that alternates between two
// processors without waiting is held handoff_ns longer; guided takes halve the pool at
// one processor; the guided formulas themselves; the lock calibration's fit.
#include "core/parallel/trace.h"
#include "experiments/sim/lock_calibration.h"
#include "experiments/sim/simulator.h"
#include "tests/sim_config.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hrad::sim {
namespace {

/// `n` initial tasks of `duration_ns` each, no children, in iteration 1.
TaskGraph roots(int n, std::uint32_t duration_ns) {
  std::vector<TraceRecord> records;
  for (int i = 0; i < n; ++i) {
    TraceRecord r;
    r.id = (std::uint64_t{1} << 40) | static_cast<std::uint64_t>(i);
    r.duration_ns = duration_ns;
    r.iteration = 1;
    records.push_back(r);
  }
  return build_task_graph(records);
}

using test::config;

TEST(SimContention, SaturatedLockPassesOncePerHoldPlusHandoff) {
  // Zero-duration tasks, one per take: every processor always waits for the lock, so
  // at T processors each take costs hold + handoff_ns + (T − 2) × handoff_waiter_ns
  // (T − 1 waiting at each release); the loading and the final empty takes add a few
  // cycles at most.
  const int n = 2000;
  const TaskGraph g = roots(n, 0);
  CostModel k;
  k.take_op_ns = 50;
  k.handoff_ns = 300;
  k.handoff_waiter_ns = 100;
  for (Policy policy : {Policy::kStack, Policy::kBlocked}) {
    for (int p : {2, 4, 16}) {
      const double cycle = k.take_op_ns + k.handoff_ns + (p - 2) * k.handoff_waiter_ns;
      const double t = simulate(g, config(policy, p, 1, k)).time_ns();
      EXPECT_GE(t, (n - 2 * p) * cycle) << policy_name(policy) << " at " << p;
      EXPECT_LE(t, (n + 2 * p) * cycle) << policy_name(policy) << " at " << p;
    }
    // One processor never hands the lock over: only the hold counts.
    EXPECT_DOUBLE_EQ(simulate(g, config(policy, 1, 1, k)).time_ns(), (n + 2) * k.take_op_ns)
        << policy_name(policy);
  }
}

TEST(SimContention, UncontendedMigrationLengthensTheHold) {
  // Two processors, tasks much longer than a take: they never wait, but every take
  // finds the lock last held by the other one and holds it handoff_ns longer.
  const int n = 100;
  const TaskGraph g = roots(n, 10000);
  CostModel k;
  k.take_op_ns = 100;
  k.handoff_ns = 1000;
  const double round = 10000 + k.take_op_ns + k.handoff_ns;
  const double t = simulate(g, config(Policy::kStack, 2, 1, k)).time_ns();
  EXPECT_GE(t, (n / 2) * round);
  EXPECT_LE(t, (n / 2 + 2) * round);
  const SimResult r = simulate(g, config(Policy::kStack, 2, 1, k));
  EXPECT_LT(r.totals().lock_wait_ns, 0.05 * t) << "alternation without waiting";
}

TEST(SimContention, GuidedTakesHalveThePoolAtOneProcessor) {
  // 1000 tasks at one processor (T = 1): takes of ceil(P / 2): 500, 250, 125, 63, 31,
  // 16, 8, 4, 2, 1 = 10 takes, plus the empty take before loading and the final one.
  const TaskGraph g = roots(1000, 0);
  CostModel k;
  k.take_op_ns = 100;
  for (Policy policy : {Policy::kBlocked, Policy::kStack, Policy::kFifo}) {
    const SimResult r = simulate(g, config(policy, 1, 0, k));
    EXPECT_DOUBLE_EQ(r.time_ns(), 12 * k.take_op_ns) << policy_name(policy);
    EXPECT_EQ(r.totals().takes, 10u) << policy_name(policy);
  }
  // Stealing at one processor: the owner pops ceil(own / 2), the same 10 pops.
  CostModel s;
  s.local_op_ns = 100;
  const SimResult r = simulate(g, config(Policy::kStealing, 1, 0, s));
  EXPECT_EQ(r.totals().takes, 10u);
}

TEST(SimContention, GuidedTakesAreTheSchedulersFormula) {
  // The replay calls schedulers/scheduler.h's guided_block (GuidedTakesHalveThePool...
  // checks the takes it makes); pin the values the docs quote.
  EXPECT_EQ(guided_block(1000, 4), 125u);
  EXPECT_EQ(guided_block(1000, 1), 500u);
  EXPECT_EQ(guided_block(32 * 1024 + 32, 16), kGuidedMaxBlock);  // capped
  EXPECT_EQ(guided_block(0, 4), 1u);
}

TEST(SimContention, GuidedRunsEveryTaskOnceAtManyProcessors) {
  const TaskGraph g = roots(5000, 50);
  for (Policy policy : {Policy::kBlocked, Policy::kStack, Policy::kStealing}) {
    for (int p : {1, 3, 16, 64}) {
      SimConfig c = config(policy, p, 0, default_costs(policy));
      c.keep_executions = true;
      const SimResult r = simulate(g, c);
      for (std::uint32_t e : r.iterations[0].executions) ASSERT_EQ(e, 1u);
      const IterationResult& it = r.iterations[0];
      EXPECT_NEAR(it.busy_ns + it.overhead_ns + it.lock_wait_ns + it.idle_ns, p * it.time_ns,
                  1e-6 * p * it.time_ns)
          << policy_name(policy) << " at " << p;
    }
  }
}

TEST(SimContention, OutsideTheLoopIsAmdahlOverTheOneThreadTime) {
  // 1000 tasks of 1 us at P processors, no scheduler costs: the loop takes 1000 / P us;
  // the stage outside it, N = 600 us at 1 thread with serial share s = 0.25, adds
  // N (s + (1 − s) / P); every share adds up to P × time.
  const TaskGraph g = roots(1000, 1000);
  CostModel k;
  k.outside_serial_share = 0.25;
  for (int p : {1, 2, 4, 10}) {
    SimConfig c = config(Policy::kStack, p, 1, k);
    c.outside = {OutsideLoop{400'000, 150'000, 50'000}};
    const SimResult r = simulate(g, c);
    const IterationResult& it = r.iterations[0];
    const double outside = 600'000 * (0.25 + 0.75 / p);
    EXPECT_NEAR(it.time_ns, 1'000'000.0 / p + outside, 1e-6) << p;
    EXPECT_NEAR(it.outside_ns, p * outside, 1e-6) << p;
    EXPECT_NEAR(it.busy_ns + it.overhead_ns + it.lock_wait_ns + it.idle_ns + it.outside_ns,
                p * it.time_ns, 1e-6)
        << p;
    // Without an entry for the iteration: nothing is added.
    c.outside.clear();
    EXPECT_NEAR(simulate(g, c).time_ns(), 1'000'000.0 / p, 1e-6) << p;
  }
}

TEST(SimContention, FitOfHandoffSamples) {
  // handoff = 200 + 50 (k − 2), exactly.
  std::vector<HandoffSample> s;
  for (int k = 2; k <= 8; ++k) {
    HandoffSample x;
    x.threads = k;
    x.handoff_ns = 200 + 50.0 * (k - 2);
    s.push_back(x);
  }
  const HandoffFit f = fit_handoffs(s);
  EXPECT_NEAR(f.handoff_ns, 200, 1e-9);
  EXPECT_NEAR(f.handoff_waiter_ns, 50, 1e-9);
  // Two threads only: no slope.
  const HandoffFit one = fit_handoffs({s.front()});
  EXPECT_DOUBLE_EQ(one.handoff_ns, 200);
  EXPECT_DOUBLE_EQ(one.handoff_waiter_ns, 0);
}

TEST(SimContention, MeasuresAHandoffOnTwoThreads) {
  // The calibration's own measurement runs and sees the lock change hands.
  for (const HandoffSample& m : {measure_handoffs<TimedMutex>(2, 0.05, 200),
                                 measure_handoffs<TimedSpinMutex>(2, 0.05, 200)}) {
    EXPECT_GT(m.acquisitions, 100u);
    EXPECT_GT(m.change_share, 0.0);
    EXPECT_GT(m.handoff_ns, 0.0);
  }
  EXPECT_EQ(calibration_lock_names(), (std::vector<std::string>{"mutex", "spin"}));
}

}  // namespace
}  // namespace hrad::sim
