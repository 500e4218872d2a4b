#pragma once
// Semantic map files.
//  - .csm (canopy semantic map): magic "CANOPYSM", format version, the map's params and
//    classes, the tree in depth-first order (a child mask per node, a payload per leaf) and
//    an FNV-1a 64-bit checksum of everything before it. Loading round-trips exactly; a
//    truncated, corrupt or foreign file throws InputError naming the file.
//  - PLY: occupied voxels as a binary point cloud with class colours (SemanticClasses::color),
//    class index and occupancy; MeshLab and CloudCompare open it.
//  - .bt: the occupancy as a standard OctoMap OcTree binary file (octovis, ROS tools).

#include <string>

#include "canopy/mapping/semantic_octree.h"

namespace canopy::mapping {

/// Current .csm format version.
constexpr std::uint32_t kMapFormatVersion = 2;  ///< 2: entropy categories stored with the parameters.

/// Serialises a map to the .csm byte format.
std::string serialize_map(const SemanticOcTree& map);
/// Parses .csm bytes; `name` names the source in errors. Throws InputError on bad data.
SemanticOcTree deserialize_map(const std::string& bytes, const std::string& name);

/// Writes `path` atomically.
void save_map(const SemanticOcTree& map, const std::string& path);
/// Reads a .csm file; throws InputError when missing, truncated or corrupt.
SemanticOcTree load_map(const std::string& path);

/// Writes the occupied voxels (p_occ > 0.5) as binary little-endian PLY; returns the count.
std::size_t export_ply(const SemanticOcTree& map, const std::string& path);
/// Writes the occupancy (l_occ per leaf, pruned blocks kept) as an OctoMap .bt file.
void export_bt(const SemanticOcTree& map, const std::string& path);

}  // namespace canopy::mapping
