// Draws typed values from a fuzzer's input bytes, front to back.
//
// Every draw is defined for every input (an exhausted input yields the low end
// of each range and empty byte strings), so a harness never needs to check
// lengths, and small mutations of the input stay small changes of what is
// drawn, which is what lets libFuzzer's coverage feedback make progress.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tristereo::fuzz {

class FuzzInput {
 public:
  FuzzInput(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::size_t remaining() const { return size_ - pos_; }

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }

  // An integer in [lo, hi] (inclusive; lo <= hi) from as few bytes as the span needs.
  std::int64_t in_range(std::int64_t lo, std::int64_t hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);
    std::uint64_t v = 0;
    for (std::uint64_t left = span; left != 0; left >>= 8) v = (v << 8) | byte();
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(lo) + (span == ~0ull ? v : v % (span + 1)));
  }
  int int_in(int lo, int hi) { return static_cast<int>(in_range(lo, hi)); }
  bool flag() { return (byte() & 1) != 0; }

  // Up to n bytes (fewer when the input runs out).
  std::vector<std::uint8_t> bytes(std::size_t n) {
    const std::size_t k = n < remaining() ? n : remaining();
    std::vector<std::uint8_t> out(data_ + pos_, data_ + pos_ + k);
    pos_ += k;
    return out;
  }
  // The rest of the input.
  std::vector<std::uint8_t> rest() { return bytes(remaining()); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace tristereo::fuzz
