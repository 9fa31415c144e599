// LinkList: the links stored at one receiver, as a chain of blocks taken from the
// placement arenas (core/parallel/node_arena.h) of the refiners, so that links, like elements,
// land on the node of the refiner that created them (first-touch) or where
// interleave/node0 puts them, and are counted per node.
//
// During a refinement stage, stores append: a store fills the last block's free slots
// and then adds one block, sized max(links still to store, min(links already stored,
// kMaxBlockLinks)), so no store ever copies the links before it (a growing
// std::vector would copy, and leave its old buffer on the arena, which cannot free
// it). Lists built this way are a few small blocks each, scattered among other
// receivers' blocks, and the propagation, which reads every link once per sweep, pays
// a cache miss per block: so when the stage ends, compact() moves each list into one
// block (see Hierarchy::compact_links). Links keep the order they were stored in.
//
// The memory belongs to the arena: clear() and compact() only forget blocks, and the
// arena's owner resets it when no list uses it any more (see Hierarchy). Concurrency:
// append() under the receiver's link lock; compact() by one thread per list while
// nothing appends; reading while nothing appends or compacts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>

namespace hrad {

struct Element;
class NodeArena;

/// A link r <- s, stored at the receiver r. 16 bytes.
///
/// The visibility is kept in 16 bits (steps of 1/65535, far below any estimate's noise;
/// 0 and 1 exactly), which leaves room for the visibility the oracle decided on when
/// that came from other rays than the link's own (decision_rays = independent, or a
/// surface pair's shadow test: core/solver/refiner.h). A later iteration judges the
/// link again on that value instead of casting those rays again.
struct Link {
  static constexpr std::uint16_t kOne = 0xFFFF;
  Element* source = nullptr;
  float form_factor = 0;              ///< unoccluded F_rs, receiver-area normalised
  std::uint16_t visibility_q = kOne;  ///< fraction of unblocked rays, in 1/65535
  std::uint16_t decided_q = 0;        ///< 0: none; else 1 + the decision's V in 1/65534

  Link() = default;
  /// `decided`: the visibility the oracle decided on, when not `visibility` (else < 0).
  Link(Element* s, float f, double visibility, double decided = -1)
      : source(s),
        form_factor(f),
        visibility_q(quantize(visibility, kOne)),
        decided_q(decided < 0 ? std::uint16_t{0}
                              : static_cast<std::uint16_t>(1 + quantize(decided, kOne - 1))) {}

  [[nodiscard]] double visibility() const { return visibility_q * (1.0 / kOne); }
  void set_visibility(double v) { visibility_q = quantize(v, kOne); }
  [[nodiscard]] bool has_decided() const { return decided_q != 0; }
  [[nodiscard]] double decided() const { return decided_value(decided_q); }
  /// The visibility a nonzero `decided_q` holds.
  static double decided_value(std::uint16_t q) { return (q - 1) * (1.0 / (kOne - 1)); }
  /// Irradiance at r due to s is transport() * B_s.
  [[nodiscard]] double transport() const { return static_cast<double>(form_factor) * visibility(); }

 private:
  static std::uint16_t quantize(double v, std::uint16_t one) {
    const double c = v > 0 ? (v < 1 ? v : 1.0) : 0.0;  // NaN gives 0
    return static_cast<std::uint16_t>(c * one + 0.5);
  }
};
static_assert(sizeof(Link) == 16, "links must stay small: they dominate memory");

/// A block header; its `capacity` links follow it in the same allocation.
struct LinkBlock {
  LinkBlock* next = nullptr;
  std::uint32_t count = 0;
  std::uint32_t capacity = 0;
  [[nodiscard]] Link* links() { return reinterpret_cast<Link*>(this + 1); }
  [[nodiscard]] const Link* links() const { return reinterpret_cast<const Link*>(this + 1); }
};
static_assert(sizeof(LinkBlock) == sizeof(Link), "a header takes one link's room");

class LinkList {
 public:
  /// Blocks grow with the list up to this many links (4 KiB).
  static constexpr std::uint32_t kMaxBlockLinks = 256;

  class const_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Link;
    using difference_type = std::ptrdiff_t;
    using pointer = const Link*;
    using reference = const Link&;
    const_iterator() = default;
    explicit const_iterator(const LinkBlock* b) { enter(b); }
    reference operator*() const { return *p_; }
    pointer operator->() const { return p_; }
    const_iterator& operator++() {
      if (++p_ == end_) enter(block_->next);
      return *this;
    }
    const_iterator operator++(int) {
      const_iterator t = *this;
      ++*this;
      return t;
    }
    friend bool operator==(const const_iterator& a, const const_iterator& b) {
      return a.p_ == b.p_;
    }

   private:
    void enter(const LinkBlock* b) {  // blocks are never empty
      block_ = b;
      p_ = b ? b->links() : nullptr;
      end_ = b ? p_ + b->count : nullptr;
    }
    const LinkBlock* block_ = nullptr;
    const Link* p_ = nullptr;    ///< the current link (null at the end)
    const Link* end_ = nullptr;  ///< one past the current block's links
  };

  [[nodiscard]] const_iterator begin() const { return const_iterator(head_); }
  [[nodiscard]] const_iterator end() const { return {}; }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  /// Arena bytes the blocks take (headers and free slots included).
  [[nodiscard]] std::size_t bytes() const;
  [[nodiscard]] std::size_t block_count() const;

  /// Appends `links` in order, new blocks coming from `arena`.
  void append(std::span<const Link> links, NodeArena& arena);
  /// Forgets the links; their memory stays with the arena (see above).
  void clear() {
    head_ = tail_ = nullptr;
    size_ = 0;
  }
  /// Moves the links, in order, into one block from `arena` (nothing when empty); the
  /// old blocks are left to their arenas.
  void compact(NodeArena& arena);

 private:
  LinkBlock* head_ = nullptr;
  LinkBlock* tail_ = nullptr;
  std::uint32_t size_ = 0;
};

}  // namespace hrad
