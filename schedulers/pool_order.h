// Pool order (`--set pool_order=submitted|address|subtree`): the central pools
// (stack, fifo, priority, blocked, locality) sort each submitted batch before it
// enters the pool, outside their lock, so that the tasks one block hands out have
// receivers close together:
//
// | pool_order | key of a task (stable sort, ascending)                                 |
// |------------|------------------------------------------------------------------------|
// | submitted  | none: the batch keeps the refiner's order (the default)                |
// | address    | the receiver's address: blocks walk arena memory in order              |
// | subtree    | the receiver's input polygon (Element::face), then its address: blocks |
// |            | stay inside one polygon's quadtree, whose siblings are contiguous      |
//
// Only the order inside a batch changes; which batch a take reaches first is the
// pool's own rule (LIFO, FIFO, priority). `stealing` keeps its deques as they are.
// With `subtree` the receiver is read (Element::face), so tasks must hold real
// elements; `submitted` and `address` never dereference it.
#pragma once

#include "core/hierarchy/element.h"
#include "schedulers/scheduler.h"

#include <algorithm>
#include <span>
#include <stdexcept>
#include <string>

namespace hrad {

/// Sorts `batch` by the key of `order` (stable; nothing happens for Submitted).
inline void order_batch(std::span<Task> batch, PoolOrder order) {
  if (order == PoolOrder::Address) {
    std::stable_sort(batch.begin(), batch.end(), [](const Task& a, const Task& b) {
      return std::less<>()(a.receiver, b.receiver);
    });
  } else if (order == PoolOrder::Subtree) {
    std::stable_sort(batch.begin(), batch.end(), [](const Task& a, const Task& b) {
      if (a.receiver->face != b.receiver->face) return a.receiver->face < b.receiver->face;
      return std::less<>()(a.receiver, b.receiver);
    });
  }
}

}  // namespace hrad
