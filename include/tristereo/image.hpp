// Image containers.
//
// ImageView<T> is a non-owning view with an explicit row stride in *bytes*, so
// any caller layout (padded rows, sub-images, camera DMA buffers) can be passed
// without copying. Image<T> owns tightly packed pixels and hands out views.
// Colour images interleave `channels` samples per pixel (RGB order).
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace tristereo {

template <typename T>
struct ImageView {
  T* data = nullptr;
  int width = 0;            // pixels
  int height = 0;           // rows
  int channels = 1;         // 1 = gray, 3 = RGB
  std::ptrdiff_t stride_bytes = 0;  // distance between row starts

  T* row(int y) const {
    return reinterpret_cast<T*>(reinterpret_cast<std::uintptr_t>(data) +
                                static_cast<std::ptrdiff_t>(y) * stride_bytes);
  }
  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }

  // A mutable view converts to a read-only one.
  template <typename U = T, typename = std::enable_if_t<!std::is_const<U>::value>>
  operator ImageView<const U>() const {
    return {data, width, height, channels, stride_bytes};
  }
};

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> pixels;  // width * height * channels, row-major, no padding

  Image() = default;
  Image(int w, int h, int c = 1, T fill = T())
      : width(w), height(h), channels(c),
        pixels(static_cast<std::size_t>(w) * h * c, fill) {}

  T* row(int y) { return pixels.data() + static_cast<std::size_t>(y) * width * channels; }
  const T* row(int y) const {
    return pixels.data() + static_cast<std::size_t>(y) * width * channels;
  }
  T& at(int x, int y, int c = 0) { return row(y)[x * channels + c]; }
  const T& at(int x, int y, int c = 0) const { return row(y)[x * channels + c]; }

  ImageView<T> view() {
    return {pixels.data(), width, height, channels,
            static_cast<std::ptrdiff_t>(sizeof(T)) * width * channels};
  }
  ImageView<const T> view() const {
    return {pixels.data(), width, height, channels,
            static_cast<std::ptrdiff_t>(sizeof(T)) * width * channels};
  }
};

using ImageU8 = Image<std::uint8_t>;
using ImageViewU8 = ImageView<const std::uint8_t>;
using ImageF32 = Image<float>;
using ImageS16 = Image<std::int16_t>;

}  // namespace tristereo
