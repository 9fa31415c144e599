#include "core/hierarchy/link_list.h"

#include "core/parallel/node_arena.h"

#include <algorithm>
#include <new>

namespace hrad {

std::size_t LinkList::bytes() const {
  std::size_t n = 0;
  for (const LinkBlock* b = head_; b != nullptr; b = b->next)
    n += sizeof(LinkBlock) + std::size_t{b->capacity} * sizeof(Link);
  return n;
}

std::size_t LinkList::block_count() const {
  std::size_t n = 0;
  for (const LinkBlock* b = head_; b != nullptr; b = b->next) ++n;
  return n;
}

namespace {
LinkBlock* new_block(NodeArena& arena, std::uint32_t count, std::uint32_t capacity) {
  void* p =
      arena.allocate(sizeof(LinkBlock) + std::size_t{capacity} * sizeof(Link), alignof(LinkBlock));
  return new (p) LinkBlock{nullptr, count, capacity};
}
}  // namespace

void LinkList::compact(NodeArena& arena) {
  if (size_ == 0) return;
  LinkBlock* b = new_block(arena, size_, size_);
  std::copy(begin(), end(), b->links());
  head_ = tail_ = b;
}

void LinkList::append(std::span<const Link> links, NodeArena& arena) {
  std::size_t i = 0;
  if (tail_ != nullptr) {
    const std::size_t room = std::min<std::size_t>(tail_->capacity - tail_->count, links.size());
    std::copy_n(links.begin(), room, tail_->links() + tail_->count);
    tail_->count += static_cast<std::uint32_t>(room);
    i = room;
  }
  if (i < links.size()) {
    const auto rest = static_cast<std::uint32_t>(links.size() - i);
    const std::uint32_t capacity = std::max(rest, std::min(size_, kMaxBlockLinks));
    LinkBlock* b = new_block(arena, rest, capacity);
    std::copy(links.begin() + static_cast<std::ptrdiff_t>(i), links.end(), b->links());
    (tail_ != nullptr ? tail_->next : head_) = b;
    tail_ = b;
  }
  size_ += static_cast<std::uint32_t>(links.size());
}

}  // namespace hrad
