// NodeArena: one refiner's monotonic allocator, in page-aligned chunks that each
// record their owner (the refiner) and the NUMA node their pages are on, so that
// placement studies can count, without asking the OS, where every element lives.
//
// | placement   | chunk memory                                    | node of a byte        |
// |-------------|-------------------------------------------------|-----------------------|
// | first-touch | fresh anonymous pages, written first by the     | the owner's node      |
// |             | owner, so the OS puts them on the owner's node  | (pinned, else 0)      |
// | interleave  | bound round-robin over all nodes before use     | page number mod nodes |
// | node0       | bound to node 0 before use                      | 0                     |
//
// "The owner's node" is the node of the refiner's pin plan (core/parallel/pin_plan.h); an
// unpinned refiner is counted as node 0, which is exact on a one-node machine only.
// Linux interleaves an anonymous mapping by page number within the mapping's pages
// (page address / page size for anonymous memory), which is the estimate used here.
// On a topology that is not this machine's (HWLOC_SYNTHETIC), binding is only
// planned: the bookkeeping is what placement would give on that machine.
//
// Chunks come straight from mmap (kChunkBytes, or more for a bigger request), so their
// pages are untouched when bound or first written: malloc could hand back pages some
// other thread already touched. Memory is released when the arena is destroyed, or
// handed out again after reset(), which keeps the chunks (and so the node their pages
// are on) for the same owner; the arena never runs destructors (its user does). Not
// thread-safe: one arena per refiner, used only by that refiner (the owner) or while
// no refiner runs.
#pragma once

#include "core/parallel/topology.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hrad {

/// How a set of arenas places memory, and on which node each owner runs.
struct ArenaPlacement {
  MemBind how = MemBind::FirstTouch;
  int nodes = 1;                       ///< NUMA nodes (logical indices 0 .. nodes-1)
  std::vector<int> owner_node;         ///< node of each owner (refiner); missing = 0
  const Topology* topology = nullptr;  ///< binds interleave/node0 chunks; null: bookkeeping only
};

/// Adds per-node byte counts `more` into `total` (growing it to the longer size).
void add_bytes_per_node(std::vector<std::uint64_t>& total, const std::vector<std::uint64_t>& more);

class NodeArena {
 public:
  static constexpr std::size_t kPageBytes = 4096;
  static constexpr std::size_t kChunkBytes = std::size_t{1} << 18;  ///< 256 KiB

  NodeArena(int owner, const ArenaPlacement& placement);
  ~NodeArena();
  NodeArena(const NodeArena&) = delete;
  NodeArena& operator=(const NodeArena&) = delete;

  /// `bytes` of raw memory aligned to `align` (a power of two <= kPageBytes).
  [[nodiscard]] void* allocate(std::size_t bytes, std::size_t align);

  /// Forgets everything handed out (the caller no longer uses it) and hands the same
  /// chunks out again, from the first, before mapping new ones.
  void reset();

  /// The node holding the byte at `p` (which must come from this arena), by the
  /// placement's rule above; -1 when `p` is not in this arena. O(1) for memory
  /// from the chunk being handed out, O(chunks) at worst.
  [[nodiscard]] int node_of(const void* p) const;
  [[nodiscard]] bool owns(const void* p) const { return node_of(p) >= 0; }

  [[nodiscard]] int owner() const { return owner_; }
  [[nodiscard]] int node() const { return node_; }  ///< the owner's node
  /// Bytes handed out since construction or reset(), alignment padding included.
  [[nodiscard]] std::size_t bytes_used() const { return used_; }
  [[nodiscard]] std::size_t chunk_count() const { return chunks_.size(); }  ///< mapped
  /// bytes_used() by node (size = placement.nodes).
  [[nodiscard]] std::vector<std::uint64_t> bytes_per_node() const;
  /// Up to `max` pages handed out (evenly spread over them), each with the node this
  /// arena counts it on, for checking the bookkeeping against the OS
  /// (Topology::node_of_address).
  [[nodiscard]] std::vector<std::pair<const void*, int>> sample_pages(std::size_t max) const;
  /// Chunks whose memory binding hwloc refused (the first reason in `warning`).
  [[nodiscard]] int bind_failures(std::string* warning = nullptr) const;
  /// Outcome of binding this arena's chunks: Applied (or nothing to bind), Planned
  /// (synthetic topology) or Failed (at least one chunk).
  [[nodiscard]] BindOutcome binding() const { return binding_; }

 private:
  // A line each: the current chunk's `used` is written on every allocation, and the
  // vector's buffer must not share a line with memory another thread writes.
  struct alignas(64) Chunk {
    std::byte* base;
    std::size_t size;
    std::size_t used;
  };
  void new_chunk(std::size_t at_least);
  [[nodiscard]] int node_of_page(std::uintptr_t address) const;

  int owner_;
  int node_;
  MemBind how_;
  int nodes_;
  const Topology* topology_;
  std::vector<Chunk> chunks_;
  std::size_t current_ = 0;  ///< the chunk allocate() hands out from (chunks before it are done)
  std::size_t used_ = 0;
  BindOutcome binding_ = BindOutcome::Applied;
  int bind_failures_ = 0;
  std::string first_warning_;
};

}  // namespace hrad
