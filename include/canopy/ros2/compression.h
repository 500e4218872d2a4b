#pragma once
// The chunk compressions of MCAP: none (""), "lz4" (the LZ4 frame format, liblz4) and "zstd"
// (a Zstandard frame, libzstd). Decompression fills a buffer of the size the chunk declares and
// never more, so a forged size or a decompression bomb cannot allocate beyond it.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace canopy::ros2 {

/// An MCAP chunk compression.
enum class Compression { kNone, kLz4, kZstd };

/// The name an MCAP Chunk record gives: "", "lz4", "zstd".
std::string_view compression_name(Compression c);
/// The compression named `name` in a Chunk record; nullopt for one canopy cannot read.
std::optional<Compression> parse_compression(std::string_view name);

/// Compresses chunks, one context kept across calls.
class Compressor {
 public:
  /// `level`: 0 is the library's default (zstd 3, lz4 fast); zstd takes 1..19, lz4 1..12 (below 3
  /// its fast mode).
  explicit Compressor(Compression compression, int level = 0);
  ~Compressor();
  Compressor(const Compressor&) = delete;
  Compressor& operator=(const Compressor&) = delete;
  Compression compression() const { return compression_; }
  /// Replaces `out` with `in` compressed (a copy for kNone).
  void compress(std::string_view in, std::string& out);

 private:
  struct Contexts;
  Compression compression_;
  int level_;
  std::unique_ptr<Contexts> ctx_;
};

/// Decompresses chunks, one context kept across calls.
class Decompressor {
 public:
  Decompressor();
  ~Decompressor();
  Decompressor(const Decompressor&) = delete;
  Decompressor& operator=(const Decompressor&) = delete;
  /// Decompresses `in` into exactly `out_size` bytes at `out`. Throws InputError (a short
  /// reason, without the file: the caller adds it) when the data is corrupt, ends early, or
  /// decompresses to more or fewer bytes than `out_size`.
  void decompress(Compression compression, std::string_view in, char* out, std::size_t out_size);
  /// Throws InputError when the frame headers in `in` declare another size than `out_size` (a
  /// check before the output is allocated; frames that declare no size pass).
  static void check_declared_size(Compression compression, std::string_view in, std::size_t out_size);

 private:
  struct Contexts;
  std::unique_ptr<Contexts> ctx_;
};

}  // namespace canopy::ros2
