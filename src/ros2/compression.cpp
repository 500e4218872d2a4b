#include "canopy/ros2/compression.h"

#include <lz4frame.h>
#include <zstd.h>
#include <zstd_errors.h>

#include <cstring>

#include "canopy/common/error.h"

namespace canopy::ros2 {

std::string_view compression_name(Compression c) {
  switch (c) {
    case Compression::kNone:
      return "";
    case Compression::kLz4:
      return "lz4";
    case Compression::kZstd:
      return "zstd";
  }
  return "";
}

std::optional<Compression> parse_compression(std::string_view name) {
  for (Compression c : {Compression::kNone, Compression::kLz4, Compression::kZstd})
    if (name == compression_name(c)) return c;
  return std::nullopt;
}

namespace compression_detail {  // named: the contexts' members are of this type
// Frees a library context with the library's own function.
template <class T, auto free_context>
struct Free {
  void operator()(T* p) const { free_context(p); }
};
}  // namespace compression_detail
using compression_detail::Free;

struct Compressor::Contexts {
  std::unique_ptr<ZSTD_CCtx, Free<ZSTD_CCtx, ZSTD_freeCCtx>> zstd;
  std::unique_ptr<LZ4F_cctx, Free<LZ4F_cctx, LZ4F_freeCompressionContext>> lz4;
};

Compressor::Compressor(Compression compression, int level)
    : compression_(compression), level_(level), ctx_(std::make_unique<Contexts>()) {
  if (compression_ == Compression::kZstd) {
    ctx_->zstd.reset(ZSTD_createCCtx());
    CANOPY_CHECK(ctx_->zstd != nullptr, "ZSTD_createCCtx failed");
  } else if (compression_ == Compression::kLz4) {
    LZ4F_cctx* c = nullptr;
    CANOPY_CHECK(!LZ4F_isError(LZ4F_createCompressionContext(&c, LZ4F_VERSION)), "LZ4F_createCompressionContext failed");
    ctx_->lz4.reset(c);
  }
}

Compressor::~Compressor() = default;

void Compressor::compress(std::string_view in, std::string& out) {
  switch (compression_) {
    case Compression::kNone:
      out.assign(in.data(), in.size());
      return;
    case Compression::kZstd: {
      out.resize(ZSTD_compressBound(in.size()));
      const std::size_t n = ZSTD_compressCCtx(ctx_->zstd.get(), out.data(), out.size(), in.data(), in.size(),
                                              level_ == 0 ? ZSTD_CLEVEL_DEFAULT : level_);
      CANOPY_CHECK(!ZSTD_isError(n), "zstd compression failed: " << ZSTD_getErrorName(n));
      out.resize(n);
      return;
    }
    case Compression::kLz4: {
      LZ4F_preferences_t prefs;
      std::memset(&prefs, 0, sizeof(prefs));
      prefs.frameInfo.contentSize = in.size();  // lets a reader check the size before decoding
      prefs.compressionLevel = level_;
      out.resize(LZ4F_HEADER_SIZE_MAX + LZ4F_compressBound(in.size(), &prefs));
      std::size_t pos = LZ4F_compressBegin(ctx_->lz4.get(), out.data(), out.size(), &prefs);
      CANOPY_CHECK(!LZ4F_isError(pos), "lz4 frame header: " << LZ4F_getErrorName(pos));
      const std::size_t body = LZ4F_compressUpdate(ctx_->lz4.get(), out.data() + pos, out.size() - pos, in.data(), in.size(),
                                                   nullptr);
      CANOPY_CHECK(!LZ4F_isError(body), "lz4 compression failed: " << LZ4F_getErrorName(body));
      pos += body;
      const std::size_t end = LZ4F_compressEnd(ctx_->lz4.get(), out.data() + pos, out.size() - pos, nullptr);
      CANOPY_CHECK(!LZ4F_isError(end), "lz4 frame end: " << LZ4F_getErrorName(end));
      out.resize(pos + end);
      return;
    }
  }
}

struct Decompressor::Contexts {
  std::unique_ptr<ZSTD_DCtx, Free<ZSTD_DCtx, ZSTD_freeDCtx>> zstd;
  std::unique_ptr<LZ4F_dctx, Free<LZ4F_dctx, LZ4F_freeDecompressionContext>> lz4;
};

Decompressor::Decompressor() : ctx_(std::make_unique<Contexts>()) {}
Decompressor::~Decompressor() = default;

void Decompressor::check_declared_size(Compression compression, std::string_view in, std::size_t out_size) {
  const auto size_text = [](unsigned long long n) { return std::to_string(n) + " bytes"; };
  if (compression == Compression::kZstd) {
    const unsigned long long n = ZSTD_getFrameContentSize(in.data(), in.size());
    if (n == ZSTD_CONTENTSIZE_ERROR) throw InputError("corrupt zstd data (its frame header does not parse)");
    if (n == ZSTD_CONTENTSIZE_UNKNOWN) return;
    // The first frame may not declare more than the whole; a lone frame must declare all of it.
    const bool alone = ZSTD_findFrameCompressedSize(in.data(), in.size()) == in.size();
    if (n > out_size || (alone && n != out_size))
      throw InputError("a zstd frame declaring " + size_text(n) + ", not the " + size_text(out_size) + " declared");
  } else if (compression == Compression::kLz4) {
    // Frame header: magic 04 22 4D 18, FLG (bit 3: a content size follows BD), BD, size.
    const auto* b = reinterpret_cast<const unsigned char*>(in.data());
    if (in.size() >= 14 && b[0] == 0x04 && b[1] == 0x22 && b[2] == 0x4D && b[3] == 0x18 && (b[4] & 0x08) != 0) {
      std::uint64_t n = 0;
      std::memcpy(&n, b + 6, 8);
      if (n > out_size)  // more frames may follow: the first may not declare more than all
        throw InputError("an lz4 frame declaring " + size_text(n) + ", more than the " + size_text(out_size) +
                         " declared");
    }
  }
}

void Decompressor::decompress(Compression compression, std::string_view in, char* out, std::size_t out_size) {
  const auto size_text = [](std::size_t n) { return std::to_string(n) + " bytes"; };
  if (compression == Compression::kNone) {
    if (in.size() != out_size)
      throw InputError("uncompressed records of " + size_text(in.size()) + ", not the " + size_text(out_size) +
                       " declared");
    if (out_size > 0) std::memcpy(out, in.data(), out_size);
    return;
  }
  if (in.empty() && out_size == 0) return;
  if (compression == Compression::kZstd) {
    if (ctx_->zstd == nullptr) {
      ctx_->zstd.reset(ZSTD_createDCtx());
      CANOPY_CHECK(ctx_->zstd != nullptr, "ZSTD_createDCtx failed");
    }
    // zstd's default window limit (128 MiB) bounds its own memory; the output is `out_size`.
    const std::size_t n = ZSTD_decompressDCtx(ctx_->zstd.get(), out, out_size, in.data(), in.size());
    if (ZSTD_isError(n)) {
      if (ZSTD_getErrorCode(n) == ZSTD_error_dstSize_tooSmall)
        throw InputError("zstd data decompresses to more than the " + size_text(out_size) + " declared");
      throw InputError(std::string("corrupt zstd data (") + ZSTD_getErrorName(n) + ")");
    }
    if (n != out_size)
      throw InputError("zstd data decompresses to " + size_text(n) + ", not the " + size_text(out_size) + " declared");
    return;
  }
  // LZ4 frames (one or more, back to back).
  if (ctx_->lz4 == nullptr) {
    LZ4F_dctx* d = nullptr;
    CANOPY_CHECK(!LZ4F_isError(LZ4F_createDecompressionContext(&d, LZ4F_VERSION)),
                 "LZ4F_createDecompressionContext failed");
    ctx_->lz4.reset(d);
  }
  LZ4F_resetDecompressionContext(ctx_->lz4.get());  // a previous call may have stopped inside a frame
  std::size_t in_pos = 0;
  std::size_t out_pos = 0;
  while (true) {
    std::size_t dst = out_size - out_pos;
    std::size_t src = in.size() - in_pos;
    const std::size_t hint = LZ4F_decompress(ctx_->lz4.get(), out + out_pos, &dst, in.data() + in_pos, &src, nullptr);
    if (LZ4F_isError(hint)) throw InputError(std::string("corrupt lz4 data (") + LZ4F_getErrorName(hint) + ")");
    in_pos += src;
    out_pos += dst;
    if (hint == 0 && in_pos == in.size()) break;  // the last frame is complete
    if (src == 0 && dst == 0) {
      if (in_pos == in.size()) throw InputError("lz4 data ends inside a frame");
      throw InputError("lz4 data decompresses to more than the " + size_text(out_size) + " declared");
    }
  }
  if (out_pos != out_size)
    throw InputError("lz4 data decompresses to " + size_text(out_pos) + ", not the " + size_text(out_size) +
                     " declared");
}

}  // namespace canopy::ros2
