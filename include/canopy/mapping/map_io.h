#pragma once
// Semantic map files.
//  - .csm (canopy semantic map): magic "CANOPYSM", format version, the map's params and
//    classes, the tree in depth-first order (a child mask per node, a payload per leaf) and
//    an FNV-1a 64-bit checksum of everything before it. Loading round-trips exactly; a
//    truncated, corrupt or foreign file throws InputError naming the file.
//  - PLY: occupied voxels as a binary point cloud with class colours (SemanticClasses::color),
//    class index and occupancy; MeshLab and CloudCompare open it.
//  - .bt: the occupancy as a standard OctoMap OcTree binary file (octovis, ROS tools).
//  - .csm.zst: the .csm bytes in one Zstandard frame (the `zstd` tool reads it), about a
//    twentyfifth of the size; read back, the very same .csm bytes. load_map reads both.

#include <string>

#include "canopy/mapping/semantic_octree.h"

namespace canopy::mapping {

/// Current .csm format version.
constexpr std::uint32_t kMapFormatVersion = 2;  ///< 2: entropy categories stored with the parameters.

/// Serialises a map to the .csm byte format.
std::string serialize_map(const SemanticOcTree& map);
/// Parses .csm bytes; `name` names the source in errors. Throws InputError on bad data.
SemanticOcTree deserialize_map(const std::string& bytes, const std::string& name);

/// Zstandard level of .csm.zst files: 12 compresses a default mission's 17 MB map to about
/// 0.7 MB in about 0.5 s (9: 0.76 MB in 0.4 s; 3: 1.0 MB in 0.2 s; 19: 0.48 MB in 13 s).
constexpr int kMapZstdLevel = 12;

/// True when `path` names a compressed map (ends in ".zst").
bool compressed_map_path(const std::string& path);
/// `csm` (serialize_map's bytes) in one Zstandard frame that declares its size.
std::string compress_map_bytes(const std::string& csm, int level = kMapZstdLevel);
/// The .csm bytes of `bytes`: decompressed when they are a Zstandard frame, else as they are.
/// `name` names the source in errors; throws InputError on a damaged frame.
std::string map_bytes(const std::string& bytes, const std::string& name);

/// Writes `path` atomically, compressed when it ends in ".zst" (compressed_map_path).
void save_map(const SemanticOcTree& map, const std::string& path);
/// Reads a .csm or .csm.zst file (by its bytes, not its name); throws InputError when
/// missing, truncated or corrupt.
SemanticOcTree load_map(const std::string& path);

/// Writes the occupied voxels (p_occ > 0.5) as binary little-endian PLY; returns the count.
std::size_t export_ply(const SemanticOcTree& map, const std::string& path);
/// Writes the occupancy (l_occ per leaf, pruned blocks kept) as an OctoMap .bt file.
void export_bt(const SemanticOcTree& map, const std::string& path);

}  // namespace canopy::mapping
