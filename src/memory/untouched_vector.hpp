// Working buffers that configure() allocates without touching their pages.
//
// std::vector<T>(n) and resize(n) value-initialise: for trivial T they write n
// zeros, so every page of a large buffer is faulted in (and zeroed twice: by
// the kernel, then by the vector) before the first frame, even the pages a
// smaller frame never uses. UntouchedVector<T>(n) and resize(n) default-
// initialise instead: for trivial T nothing is written, a large block stays
// untouched address space (glibc serves it by mmap) until a frame writes it.
// Use it only for buffers every reader writes before it reads; elements of
// non-trivial types are still constructed.
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace tristereo {

template <typename T>
class DefaultInitAllocator : public std::allocator<T> {
 public:
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}  // NOLINT: allocators convert

  // The one change from std::allocator: no arguments means default-init.
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T, typename U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return true;
}
template <typename T, typename U>
bool operator!=(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return false;
}

template <typename T>
using UntouchedVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace tristereo
