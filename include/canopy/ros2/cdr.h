#pragma once
// CDR, the encoding of ROS 2 messages (XCDR1, little-endian; what rmw_fastrtps and rosbag2 write):
// a 4-byte encapsulation header 00 01 00 00, then the fields in order, each primitive aligned to
// its own size (8 at most) counted from the byte after the header. A string is a uint32 length
// counting its terminating NUL, the bytes and the NUL; a sequence (T[]) a uint32 count and its
// elements; a fixed array (T[N]) its elements only; a bool one byte; a nested message its fields.
//
// CdrWriter and CdrReader share one call syntax, `cdr(field)`, so that each message states its
// fields once (messages.cpp) and both directions follow from that list.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "canopy/common/error.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "canopy's CDR code copies little-endian values as they lie in memory"
#endif

namespace canopy::ros2 {

/// The encapsulation header of little-endian plain CDR (XCDR1), before every ROS 2 message.
constexpr std::array<std::uint8_t, 4> kCdrLittleEndianHeader = {0x00, 0x01, 0x00, 0x00};

namespace detail {
template <class T> struct IsVector : std::false_type {};
template <class T, class A> struct IsVector<std::vector<T, A>> : std::true_type {};
template <class T> struct IsArray : std::false_type {};
template <class T, std::size_t N> struct IsArray<std::array<T, N>> : std::true_type {};
/// A primitive whose bytes are copied as they are (bool is written as one byte 0 or 1 instead).
template <class T> constexpr bool kIsPlain = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;
}  // namespace detail

/// Serialises a ROS 2 message into CDR bytes, header included. Fields go in by `w(field)`:
/// primitives, std::string, std::vector (a sequence), std::array (a fixed array) and messages,
/// for which an `encode(CdrWriter&, const M&)` is found by argument-dependent lookup.
class CdrWriter {
 public:
  CdrWriter() { reset(); }
  /// Starts a new message (the header alone), keeping the buffer's capacity.
  void reset() {
    buf_.assign(reinterpret_cast<const char*>(kCdrLittleEndianHeader.data()), kCdrLittleEndianHeader.size());
  }
  /// The message so far, header included.
  const std::string& bytes() const { return buf_; }
  /// Moves the message out (the writer starts again empty).
  std::string take() {
    std::string out = std::move(buf_);
    reset();
    return out;
  }

  template <class T>
  void operator()(const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      buf_.push_back(v ? '\1' : '\0');
    } else if constexpr (detail::kIsPlain<T>) {
      align(sizeof(T));
      append(&v, sizeof(T));
    } else if constexpr (std::is_same_v<T, std::string>) {
      // The length counts the NUL.
      const std::uint32_t n = static_cast<std::uint32_t>(v.size() + 1);
      (*this)(n);
      buf_.append(v);
      buf_.push_back('\0');
    } else if constexpr (detail::IsVector<T>::value) {
      using E = typename T::value_type;
      static_assert(!std::is_same_v<E, bool>, "bool[] is not used by the messages canopy writes");
      (*this)(static_cast<std::uint32_t>(v.size()));
      elements(v.data(), v.size());
    } else if constexpr (detail::IsArray<T>::value) {
      elements(v.data(), v.size());
    } else {
      encode(*this, v);
    }
  }

 private:
  template <class E>
  void elements(const E* p, std::size_t n) {
    if constexpr (detail::kIsPlain<E>) {
      if (n == 0) return;
      align(sizeof(E));
      append(p, n * sizeof(E));
    } else {
      for (std::size_t i = 0; i < n; ++i) (*this)(p[i]);
    }
  }
  void align(std::size_t size) {
    const std::size_t body = buf_.size() - kCdrLittleEndianHeader.size();
    const std::size_t pad = (size - body % size) % size;
    buf_.append(pad, '\0');
  }
  void append(const void* p, std::size_t n) { buf_.append(static_cast<const char*>(p), n); }

  std::string buf_;
};

/// Reads a ROS 2 message from CDR bytes. Every length and count is checked against the bytes
/// left before anything is allocated; a message that ends early, a string without its NUL or
/// another encapsulation than little-endian CDR throws InputError (one line, the offset).
class CdrReader {
 public:
  /// `what` names the message in errors ("sensor_msgs/msg/Image").
  CdrReader(std::string_view bytes, std::string what) : data_(bytes), what_(std::move(what)) {
    if (data_.size() < kCdrLittleEndianHeader.size())
      fail("has " + std::to_string(data_.size()) + " bytes, fewer than the 4 of the CDR encapsulation header");
    if (static_cast<std::uint8_t>(data_[0]) != 0x00 || static_cast<std::uint8_t>(data_[1]) != 0x01)
      fail("is not little-endian CDR (encapsulation header " + hex_byte(data_[0]) + " " + hex_byte(data_[1]) +
           ", expected 00 01)");
    pos_ = kCdrLittleEndianHeader.size();
  }
  /// Bytes not read yet (a message may end in up to 3 bytes of padding).
  std::size_t remaining() const { return data_.size() - pos_; }

  template <class T>
  void operator()(T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      need(1, "a bool");
      v = data_[pos_++] != '\0';
    } else if constexpr (detail::kIsPlain<T>) {
      align(sizeof(T));
      need(sizeof(T), "a number");
      std::memcpy(&v, data_.data() + pos_, sizeof(T));
      pos_ += sizeof(T);
    } else if constexpr (std::is_same_v<T, std::string>) {
      std::uint32_t n = 0;
      (*this)(n);
      need(n, "a string of " + std::to_string(n) + " bytes");
      if (n == 0) {  // not what ROS writes for "", but unambiguous
        v.clear();
        return;
      }
      if (data_[pos_ + n - 1] != '\0') fail("has a string without its terminating NUL at byte " + std::to_string(pos_));
      v.assign(data_.data() + pos_, n - 1);
      pos_ += n;
    } else if constexpr (detail::IsVector<T>::value) {
      using E = typename T::value_type;
      std::uint32_t n = 0;
      (*this)(n);
      // Every element takes at least one byte (its size for a primitive): a count beyond the
      // bytes left is refused before the vector is sized.
      if constexpr (detail::kIsPlain<E>) {
        if (n > 0) align(sizeof(E));
        need(std::size_t(n) * sizeof(E), "a sequence of " + std::to_string(n) + " elements");
      } else {
        need(n, "a sequence of " + std::to_string(n) + " elements");
      }
      v.resize(n);
      elements(v.data(), n);
    } else if constexpr (detail::IsArray<T>::value) {
      elements(v.data(), v.size());
    } else {
      decode(*this, v);
    }
  }

 private:
  template <class E>
  void elements(E* p, std::size_t n) {
    if constexpr (detail::kIsPlain<E>) {
      if (n == 0) return;
      align(sizeof(E));
      need(n * sizeof(E), "an array of " + std::to_string(n) + " elements");
      std::memcpy(p, data_.data() + pos_, n * sizeof(E));
      pos_ += n * sizeof(E);
    } else {
      for (std::size_t i = 0; i < n; ++i) (*this)(p[i]);
    }
  }
  void align(std::size_t size) {
    const std::size_t body = pos_ - kCdrLittleEndianHeader.size();
    const std::size_t pad = (size - body % size) % size;
    need(pad, "alignment padding");
    pos_ += pad;
  }
  void need(std::size_t n, const std::string& what) const {
    if (n > remaining())
      fail("ends early: " + what + " at byte " + std::to_string(pos_) + " needs " + std::to_string(n) +
           " bytes, " + std::to_string(remaining()) + " left");
  }
  [[noreturn]] void fail(const std::string& msg) const { throw InputError("CDR message " + what_ + " " + msg); }
  static std::string hex_byte(char c) {
    static const char* digits = "0123456789ABCDEF";
    const auto b = static_cast<unsigned char>(c);
    return {digits[b >> 4], digits[b & 15]};
  }

  std::string_view data_;
  std::string what_;
  std::size_t pos_ = 0;
};

}  // namespace canopy::ros2
