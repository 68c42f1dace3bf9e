#pragma once
// Fixed-length float records (one per place) in 64-byte-aligned chunks: appending never moves
// a record or over-allocates more than one chunk, and every record starts on a 64-byte
// boundary (records are padded to 16 floats), so the vector kernels load aligned data.
#include <cstddef>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

namespace loopscan {

// An owned, 64-byte-aligned float buffer (queries of the vector kernels).
class AlignedFloats {
 public:
  AlignedFloats() = default;
  explicit AlignedFloats(std::size_t n)
      : data_(static_cast<float*>(::operator new ((n + 16) * sizeof(float), std::align_val_t{64}))),
        size_(n) {
    std::memset(data_.get(), 0, (n + 16) * sizeof(float));
  }
  float* data() { return data_.get(); }
  const float* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  float& operator[](std::size_t i) { return data_.get()[i]; }
  float operator[](std::size_t i) const { return data_.get()[i]; }

 private:
  struct Delete {
    void operator()(float* p) const { ::operator delete (p, std::align_val_t{64}); }
  };
  std::unique_ptr<float, Delete> data_;
  std::size_t size_ = 0;
};

class PayloadArena {
 public:
  static constexpr std::size_t kRecordsPerChunk = 16;

  explicit PayloadArena(std::size_t floats_per_record)
      : floats_(floats_per_record), stride_((floats_per_record + 15) / 16 * 16) {}

  std::size_t size() const { return size_; }
  std::size_t floats_per_record() const { return floats_; }

  const float* at(std::size_t i) const {
    return chunks_[i / kRecordsPerChunk].get() + (i % kRecordsPerChunk) * stride_;
  }

  void append(const float* record) {
    if (size_ % kRecordsPerChunk == 0) {
      const std::size_t bytes = kRecordsPerChunk * stride_ * sizeof(float);
      chunks_.emplace_back(static_cast<float*>(::operator new (bytes, std::align_val_t{64})));
    }
    float* out = const_cast<float*>(at(size_));
    std::memcpy(out, record, floats_ * sizeof(float));
    std::memset(out + floats_, 0, (stride_ - floats_) * sizeof(float));
    ++size_;
  }

  std::size_t memory_bytes() const {
    return chunks_.size() * kRecordsPerChunk * stride_ * sizeof(float) +
           chunks_.capacity() * sizeof(Chunk);
  }

 private:
  struct AlignedDelete {
    void operator()(float* p) const { ::operator delete (p, std::align_val_t{64}); }
  };
  using Chunk = std::unique_ptr<float, AlignedDelete>;
  std::size_t floats_, stride_;
  std::size_t size_ = 0;
  std::vector<Chunk> chunks_;
};

}  // namespace loopscan
