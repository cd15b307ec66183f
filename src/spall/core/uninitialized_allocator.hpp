#pragma once
// An allocator whose default construction leaves a value as it is, and whose large blocks are pages
// of their own (memory::map_pages): a vector that a pass fills right after it grows needs no pass
// of zeros first, its pages become resident only as they are written, huge pages where the system
// grants them, and they go back to the system when it is freed (the neighbour list's entries:
// neighbors/verlet_list.hpp).
#include <cstddef>
#include <memory>
#include <new>

#include "spall/core/memory.hpp"

namespace spall {

template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  using value_type = T;
  UninitializedAllocator() = default;
  template <typename U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}  // NOLINT(google-explicit-constructor)
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  T* allocate(std::size_t n) {
    return mapped(n) ? static_cast<T*>(memory::map_pages(n * sizeof(T))) : std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, std::size_t n) {
    if (mapped(n))
      memory::unmap_pages(p, n * sizeof(T));
    else
      std::allocator<T>::deallocate(p, n);
  }
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }

 private:
  static bool mapped(std::size_t n) { return n * sizeof(T) >= (std::size_t(1) << 20); }
};

template <typename T, typename U>
bool operator==(const UninitializedAllocator<T>&, const UninitializedAllocator<U>&) {
  return true;
}

}  // namespace spall
