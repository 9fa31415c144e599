// What a stage's work is, for the stage driver (core/stage/run_stage.h): the body is
// the rule applied to each task (refinement in core/solver/refiner.cpp; a synthetic
// tree in the scheduler tests and the driver benchmark), the scheduler is the order
// (schedulers/), and the driver owns everything else: the threads, termination,
// accounting, tracing, pinning and the memory limit. Queue, policy and driver apart.
//
// A body is called on the team's threads, each worker with its own id (0..threads-1);
// the driver never calls one worker's hooks from two threads, and the calls for a
// worker come in this order:
//
// | call                          | when                                                 |
// |-------------------------------|------------------------------------------------------|
// | begin(worker, node)           | once, before the worker's first task; `node` is the  |
// |                               | NUMA node of its pin plan (0 when unpinned)          |
// | process(worker, task, out)    | every task the worker takes; new tasks go to `out`   |
// |                               | (the driver sets their ids and submits them)         |
// | end_block(worker, n) -> count | after each block of n tasks; returns the worker's    |
// |                               | results so far (shown by the progress report)        |
// | bytes_held(worker) -> bytes   | every 256 blocks when the stage has a memory limit   |
// | end_loop(worker)              | once, when no task is left (or the stage stops)       |
// | finish(worker)                | once, after every worker's end_loop (a barrier):      |
// |                               | work that needs the stage's tasks all done, timed as  |
// |                               | the stage's finish_s                                 |
//
// The body is a template parameter, not a virtual interface: process() runs once per
// task (tens of millions in a large scene) and is inlined into the driver's loop.
#pragma once

#include "schedulers/scheduler.h"

#include <concepts>
#include <cstdint>
#include <vector>

namespace hrad {

template <class B>
concept StageBody = requires(B& b, int worker, int node, const Task& task, std::vector<Task>& out,
                             std::size_t n) {
  b.begin(worker, node);
  b.process(worker, task, out);
  { b.end_block(worker, n) } -> std::convertible_to<std::uint64_t>;
  { b.bytes_held(worker) } -> std::convertible_to<std::uint64_t>;
  b.end_loop(worker);
  b.finish(worker);
};

}  // namespace hrad
