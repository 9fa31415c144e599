// UninitializedAllocator<T>: std::allocator, except that a vector's resize() leaves new
// elements of an implicit-lifetime type (an aggregate such as Task) unwritten instead of
// value-initialising them one by one on the calling thread. For a buffer that a
// parallel loop fills completely right after: growing the refinement's task list by a
// million tasks wrote 40 MB serially before the parallel fill wrote it again.
// Only for types whose every field the caller writes before reading.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>

namespace hrad {

template <class T>
class UninitializedAllocator : public std::allocator<T> {
 public:
  using value_type = T;
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  explicit UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}

  /// Value-initialisation (resize, the sized constructor): nothing is written.
  template <class U>
  void construct(U* /*p*/) noexcept {
    static_assert(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>);
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T, class U>
bool operator==(const UninitializedAllocator<T>&, const UninitializedAllocator<U>&) noexcept {
  return true;
}

}  // namespace hrad
