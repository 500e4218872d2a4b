#pragma once
// Bytes in one Zstandard frame (the `zstd` tool's format) and back: what canopy keeps
// compressed on disk (maps as .csm.zst, an experiment trial's report page). The frame declares
// its size, so reading allocates that once and never more.

#include <string>

namespace canopy {

/// `bytes` in one Zstandard frame at `level` (1..19) that declares its size.
std::string zstd_compress(const std::string& bytes, int level);
/// True when `bytes` begin with a Zstandard frame's magic number.
bool is_zstd_frame(const std::string& bytes);
/// The bytes of the frame `frame`: throws InputError naming `name` when it is damaged, does not
/// declare its size, or declares more than `max_bytes`.
std::string zstd_decompress(const std::string& frame, const std::string& name,
                            unsigned long long max_bytes = 1ull << 36);

}  // namespace canopy
