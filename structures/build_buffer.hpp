// Growing arrays of a structure build (its nodes, its leaf references) kept in chunks of fixed
// capacity. A std::vector that doubles holds its old and its new copy at once, a subtree built
// in parallel and appended to its parent is a second copy, and shrink_to_fit a third: together
// they made the kd-tree's and octree's build peaks about three times their result. Here appending
// never moves what is stored, a subtree is spliced by moving its chunks, and the result is copied
// out once, chunk by chunk, each chunk freed as soon as it is copied: the peak stays about one
// chunk above the result.
#pragma once

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace pcrt {

// Frees v's memory (`v = {}` and clear() keep the capacity).
template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

// Hands back to the system the whole pages of v's storage between its size and `touched` elements
// (the most it has held since the last call), once they come to min_bytes; returns the new
// high-water mark. A stack that grew and shrank keeps its pages resident otherwise, though no
// element there is read again (the next growth writes them first).
template <class T>
size_t release_pages_past_size(std::vector<T>& v, size_t touched, size_t min_bytes) {
  static const auto page = uintptr_t(sysconf(_SC_PAGESIZE));
  const auto base = reinterpret_cast<uintptr_t>(v.data());
  const uintptr_t lo = (base + v.size() * sizeof(T) + page - 1) & ~(page - 1);
  const uintptr_t hi = (base + std::min(touched, v.capacity()) * sizeof(T)) & ~(page - 1);
  if (hi <= lo || hi - lo < min_bytes) return std::max(touched, v.size());
  madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_DONTNEED);
  return v.size();
}

template <class T>
class ChunkedArray {
 public:
  static constexpr size_t kChunk = size_t(1) << 14;  // elements per chunk, at most
  static constexpr size_t kFirstChunk = size_t(1) << 9;
  static constexpr size_t kChunksPerTrim = 64;

  // Where an element lives: valid until the array is flattened, whatever is appended or spliced.
  struct Handle {
    size_t chunk = 0, pos = 0;
  };

  [[nodiscard]] size_t size() const { return size_; }

  Handle push_back(const T& x) { return push_n(1, x); }

  // n copies of x, contiguous within one chunk (n <= kChunk): an octree node's stored children.
  Handle push_n(size_t n, const T& x) {
    if (chunks_.empty() || chunks_.back().capacity() - chunks_.back().size() < n) new_chunk();
    std::vector<T>& c = chunks_.back();
    const Handle h{chunks_.size() - 1, c.size()};
    c.insert(c.end(), n, x);
    size_ += n;
    return h;
  }

  void append(std::span<const T> xs) {
    while (!xs.empty()) {
      if (chunks_.empty() || chunks_.back().size() == chunks_.back().capacity()) new_chunk();
      std::vector<T>& c = chunks_.back();
      const size_t n = std::min(xs.size(), c.capacity() - c.size());
      c.insert(c.end(), xs.begin(), xs.begin() + long(n));
      xs = xs.subspan(n);
      size_ += n;
    }
  }

  T& operator[](const Handle& h) { return chunks_[h.chunk][h.pos]; }

  // Moves sub's elements to the end of this array, fix(element) applied to each on the way (a
  // subtree's indices are relative to its own arrays). No element is copied.
  template <class Fix>
  void splice(ChunkedArray&& sub, Fix&& fix) {
    for (std::vector<T>& c : sub.chunks_) {
      for (T& x : c) fix(x);
      chunks_.push_back(std::move(c));
    }
    size_ += sub.size_;
    sub.chunks_.clear();
    sub.size_ = 0;
  }

  // The elements as one array of exactly size() elements; leaves this array empty. The chunks
  // are small enough to come from the allocator's heap, which keeps freed pages resident: they
  // are handed back to the system (malloc_trim) every few megabytes copied, so that the result
  // and its chunks are never all resident at once.
  std::vector<T> flatten() {
    std::vector<T> out;
    out.reserve(size_);
    size_t freed = 0;
    for (std::vector<T>& c : chunks_) {
      out.insert(out.end(), c.begin(), c.end());
      release(c);
      if (++freed % kChunksPerTrim == 0) malloc_trim(0);
    }
    chunks_.clear();
    size_ = 0;
    malloc_trim(0);
    return out;
  }

 private:
  // Chunks grow from kFirstChunk to kChunk, doubling: a build has thousands of small parallel
  // subtrees, each with a partly filled last chunk, until they are spliced.
  void new_chunk() {
    const size_t capacity = std::min(kChunk, kFirstChunk << std::min<size_t>(chunks_.size(), 16));
    chunks_.emplace_back();
    chunks_.back().reserve(capacity);
  }

  std::vector<std::vector<T>> chunks_;
  size_t size_ = 0;
};

}  // namespace pcrt
