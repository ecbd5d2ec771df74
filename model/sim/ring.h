// A FIFO ring of values on one power-of-two buffer, doubled when full: the head is one load away
// (a std::deque's is two, each a host cache miss when many queues are live), and a queue that
// stays within its first size never allocates again.
#pragma once

#include <cstddef>
#include <vector>

namespace rtsim::model {

template <class T>
class Ring {
 public:
  // `capacity`: the first buffer's size, rounded up to a power of two.
  explicit Ring(size_t capacity = 16) {
    size_t n = 1;
    while (n < capacity) n *= 2;
    buf_.resize(n);
    mask_ = n - 1;
  }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ > mask_; }
  size_t size() const { return size_; }
  // The i-th value from the head.
  T& operator[](size_t i) { return buf_[(head_ + i) & mask_]; }
  const T& operator[](size_t i) const { return buf_[(head_ + i) & mask_]; }
  const T& front() const { return buf_[head_]; }
  const T& back() const { return (*this)[size_ - 1]; }
  // By value: `x` may be one of the ring's own values, which growing would free.
  void push_back(T x) {
    if (full()) grow();
    buf_[(head_ + size_++) & mask_] = x;
  }
  void push_front(T x) {
    if (full()) grow();
    head_ = (head_ + mask_) & mask_;
    buf_[head_] = x;
    ++size_;
  }
  // Inserts `x` after the tail's run of values it goes before (`less(x, v)`), moving them one
  // place on: a sorted ring's insert, from the tail. The ring's fields are read once, not after
  // every move (a moved value's store could alias them).
  template <class Less>
  void insert_from_back(T x, Less less) {
    if (full()) grow();
    T* const buf = buf_.data();
    const size_t head = head_, mask = mask_;
    size_t i = size_++;
    for (; i > 0 && less(x, buf[(head + i - 1) & mask]); --i)
      buf[(head + i) & mask] = buf[(head + i - 1) & mask];
    buf[(head + i) & mask] = x;
  }
  void pop_front() {
    head_ = (head_ + 1) & mask_;
    --size_;
  }

 private:
  void grow() {
    std::vector<T> bigger(buf_.size() * 2);
    for (size_t i = 0; i < size_; ++i) bigger[i] = (*this)[i];
    buf_.swap(bigger);
    mask_ = buf_.size() - 1;
    head_ = 0;
  }
  std::vector<T> buf_;
  size_t mask_ = 0;  // buf_.size() - 1
  size_t head_ = 0, size_ = 0;
};

}  // namespace rtsim::model
