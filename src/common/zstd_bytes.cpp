// Bytes in one Zstandard frame and back (zstd_bytes.h).

#include "canopy/common/zstd_bytes.h"

#include <zstd.h>

#include <cstring>

#include "canopy/common/error.h"

namespace canopy {

std::string zstd_compress(const std::string& bytes, int level) {
  std::string out(ZSTD_compressBound(bytes.size()), '\0');
  const std::size_t n = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), level);
  CANOPY_CHECK(!ZSTD_isError(n), "zstd: " << ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

bool is_zstd_frame(const std::string& bytes) {
  constexpr unsigned char kMagic[4] = {0x28, 0xb5, 0x2f, 0xfd};
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kMagic, 4) == 0;
}

std::string zstd_decompress(const std::string& frame, const std::string& name, unsigned long long max_bytes) {
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    throw InputError(name + ": not a Zstandard frame that declares its size");
  if (size > max_bytes)
    throw InputError(name + ": a Zstandard frame declaring " + std::to_string(size) + " bytes, more than " +
                     std::to_string(max_bytes));
  std::string out(static_cast<std::size_t>(size), '\0');
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), frame.data(), frame.size());
  if (ZSTD_isError(n)) throw InputError(name + ": damaged Zstandard frame (" + ZSTD_getErrorName(n) + ")");
  if (n != out.size())
    throw InputError(name + ": damaged Zstandard frame (" + std::to_string(n) + " of its " + std::to_string(size) +
                     " bytes)");
  return out;
}

}  // namespace canopy
