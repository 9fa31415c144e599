// The simulator's configuration in one call, for the simulator's tests.
#pragma once

#include "experiments/sim/simulator.h"

namespace hrad::sim::test {

/// `procs` processors running `policy` with blocks of `block` tasks and `costs`.
inline SimConfig config(Policy policy, int procs, int block = 1, CostModel costs = {}) {
  SimConfig c;
  c.policy = policy;
  c.procs = procs;
  c.block_size = block;
  c.costs = costs;
  return c;
}

}  // namespace hrad::sim::test
