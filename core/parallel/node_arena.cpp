#include "core/parallel/node_arena.h"

#include <fmt/format.h>
#include <sys/mman.h>

#include <algorithm>
#include <new>
#include <stdexcept>

namespace hrad {

void add_bytes_per_node(std::vector<std::uint64_t>& total, const std::vector<std::uint64_t>& more) {
  total.resize(std::max(total.size(), more.size()), 0);
  for (std::size_t n = 0; n < more.size(); ++n) total[n] += more[n];
}

NodeArena::NodeArena(int owner, const ArenaPlacement& placement)
    : owner_(owner),
      node_(owner >= 0 && static_cast<std::size_t>(owner) < placement.owner_node.size()
                ? placement.owner_node[static_cast<std::size_t>(owner)]
                : 0),
      how_(placement.how),
      nodes_(std::max(placement.nodes, 1)),
      topology_(placement.topology) {
  if (node_ < 0 || node_ >= nodes_) node_ = 0;
}

NodeArena::~NodeArena() {
  for (const Chunk& c : chunks_) ::munmap(c.base, c.size);
}

void NodeArena::new_chunk(std::size_t at_least) {
  const std::size_t size =
      std::max(kChunkBytes, (at_least + kPageBytes - 1) / kPageBytes * kPageBytes);
  void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  chunks_.push_back(Chunk{static_cast<std::byte*>(p), size, 0});
  if (how_ == MemBind::FirstTouch || topology_ == nullptr) return;
  std::string warning;
  const BindOutcome b = topology_->bind_memory(p, size, how_, 0, &warning);
  if (b == BindOutcome::Failed) {
    if (bind_failures_++ == 0) first_warning_ = warning;
    binding_ = BindOutcome::Failed;
  } else if (b == BindOutcome::Planned && binding_ == BindOutcome::Applied) {
    binding_ = BindOutcome::Planned;
  }
}

void* NodeArena::allocate(std::size_t bytes, std::size_t align) {
  if (align == 0 || (align & (align - 1)) != 0 || align > kPageBytes)
    throw std::invalid_argument("NodeArena: alignment must be a power of two up to a page");
  for (; current_ < chunks_.size(); ++current_) {
    Chunk& c = chunks_[current_];
    const std::size_t at = (c.used + align - 1) & ~(align - 1);
    if (at + bytes <= c.size) {
      used_ += at + bytes - c.used;  // alignment padding counts as used
      c.used = at + bytes;
      return c.base + at;
    }
  }
  new_chunk(bytes);
  current_ = chunks_.size() - 1;
  Chunk& c = chunks_.back();
  c.used = bytes;
  used_ += bytes;
  return c.base;
}

void NodeArena::reset() {
  for (Chunk& c : chunks_) c.used = 0;
  used_ = 0;
  current_ = 0;
}

int NodeArena::node_of_page(std::uintptr_t address) const {
  switch (how_) {
    case MemBind::FirstTouch: return node_;
    case MemBind::Node: return 0;
    case MemBind::Interleave:
      return static_cast<int>((address / kPageBytes) % static_cast<std::uintptr_t>(nodes_));
  }
  return 0;
}

int NodeArena::node_of(const void* p) const {
  const auto* b = static_cast<const std::byte*>(p);
  const auto in = [b](const Chunk& c) { return b >= c.base && b < c.base + c.used; };
  // The chunk being handed out first: the memory just allocated is found at once.
  if (current_ < chunks_.size() && in(chunks_[current_]))
    return node_of_page(reinterpret_cast<std::uintptr_t>(p));
  for (const Chunk& c : chunks_)
    if (in(c)) return node_of_page(reinterpret_cast<std::uintptr_t>(p));
  return -1;
}

std::vector<std::uint64_t> NodeArena::bytes_per_node() const {
  std::vector<std::uint64_t> bytes(static_cast<std::size_t>(nodes_), 0);
  for (const Chunk& c : chunks_) {
    if (how_ != MemBind::Interleave) {
      bytes[static_cast<std::size_t>(node_of_page(0))] += c.used;
      continue;
    }
    const auto base = reinterpret_cast<std::uintptr_t>(c.base);
    for (std::size_t off = 0; off < c.used; off += kPageBytes)
      bytes[static_cast<std::size_t>(node_of_page(base + off))] +=
          std::min(kPageBytes, c.used - off);
  }
  return bytes;
}

std::vector<std::pair<const void*, int>> NodeArena::sample_pages(std::size_t max) const {
  std::vector<std::pair<const void*, int>> out;
  std::size_t pages = 0;
  for (const Chunk& c : chunks_) pages += (c.used + kPageBytes - 1) / kPageBytes;
  if (pages == 0 || max == 0) return out;
  const std::size_t step = (pages + max - 1) / max;
  std::size_t k = 0;  // page number over all chunks
  for (const Chunk& c : chunks_)
    for (std::size_t off = 0; off < c.used; off += kPageBytes, ++k)
      if (k % step == 0) {
        const std::byte* p = c.base + off;
        out.emplace_back(p, node_of_page(reinterpret_cast<std::uintptr_t>(p)));
      }
  return out;
}

int NodeArena::bind_failures(std::string* warning) const {
  if (warning) *warning = first_warning_;
  return bind_failures_;
}

}  // namespace hrad
