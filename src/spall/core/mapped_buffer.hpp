#pragma once
// A fixed-capacity buffer of trivially copyable values in anonymous pages of its own: a page becomes
// resident when it is first written and goes back to the system when the buffer is destroyed.
// Memory freed through malloc may stay with the process (glibc keeps blocks below its mmap threshold
// in its arenas), so a pass that copies a structure out of such buffers and frees each as it goes
// would still hold both at once; these do not (the neighbour search's row buffers,
// neighbors/verlet_list.cpp).
#include <cstddef>
#include <type_traits>
#include <utility>

#include "spall/core/memory.hpp"

namespace spall {

template <typename T>
  requires std::is_trivially_copyable_v<T>
class MappedBuffer {
 public:
  MappedBuffer() = default;
  explicit MappedBuffer(std::size_t capacity)
      : data_(static_cast<T*>(memory::map_pages(capacity * sizeof(T)))), capacity_(capacity) {}
  MappedBuffer(MappedBuffer&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)), capacity_(std::exchange(other.capacity_, 0)) {}
  MappedBuffer& operator=(MappedBuffer&& other) noexcept {
    if (this != &other) {
      release();
      data_ = std::exchange(other.data_, nullptr);
      capacity_ = std::exchange(other.capacity_, 0);
    }
    return *this;
  }
  MappedBuffer(const MappedBuffer&) = delete;
  MappedBuffer& operator=(const MappedBuffer&) = delete;
  ~MappedBuffer() { release(); }

  // Gives the pages back now; the buffer is then empty.
  void release() {
    if (data_) memory::unmap_pages(data_, capacity_ * sizeof(T));
    data_ = nullptr;
    capacity_ = 0;
  }
  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t capacity() const { return capacity_; }

 private:
  T* data_ = nullptr;
  std::size_t capacity_ = 0;
};

}  // namespace spall
