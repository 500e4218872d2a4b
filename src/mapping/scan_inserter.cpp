#include "canopy/mapping/scan_inserter.h"

#include "canopy/common/timer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/radix_sort.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/mapping/voxel_ray.h"

namespace canopy::mapping {

namespace {


constexpr std::uint64_t kInvalid = std::numeric_limits<std::uint64_t>::max();
constexpr std::uint8_t kBeyond = 255;            // label byte of a point beyond max range
constexpr std::uint64_t kBeyondFlag = 1ull << 63;  // on a ray target: no hit at its end
constexpr std::size_t kMaxGridCells = std::size_t(1) << 26;
// Below these sizes a phase runs on the calling thread (measured on 2 cores: waking a TBB
// worker costs about as much as the work it would take over).
constexpr std::size_t kParallelPoints = 100000;
constexpr std::size_t kParallelRays = 8192;
constexpr std::size_t kParallelCells = std::size_t(1) << 21;

// The ray's segment: OctoMap's arithmetic (float points), so the fast kernel and
// computeRayKeys visit the same voxels.
using Segment = RaySegment;

Segment ray_segment(const SemanticOcTree& map, const octomap::point3d& origin, std::uint64_t target,
                    double ray_range, double max_range) {
  const octomap::OcTreeKey k = morton_key(target & ~kBeyondFlag);
  const octomap::point3d c = map.keyToCoord(k);
  const double limit = (target & kBeyondFlag) ? std::min(ray_range, max_range) : ray_range;
  const octomap::point3d d = c - origin;
  if (double(d.norm()) <= limit) return {origin, c};
  return {origin, origin + d.normalized() * float(limit)};
}

// Calls visit(key) for every free cell of the segment (mapping/voxel_ray.h, OctoMap's voxels).
template <typename Visit>
void traverse(const SemanticOcTree& map, const Segment& s, Visit&& visit) {
  walk_ray(map, s.origin, s.end, [&](unsigned x, unsigned y, unsigned z) {
    visit(octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                             static_cast<octomap::key_type>(z)));
    return true;
  });
}

template <typename F>
void run_in_arena(int threads, F&& f) {
  if (threads > 1) {
    tbb::task_arena arena(threads);
    arena.execute(f);
  } else {
    f();
  }
}

// The per_endpoint insertion's voxel filter: cells of `res` on the camera's axes with a corner
// at the camera; one point per cell at the centroid of its points, with their majority label
// (ties: the smaller class). Points that are not finite or have a bad label pass unchanged
// (the inserter counts them). Deterministic: cells in order of their index.
void camera_voxel_filter(const perception::LabelledCloud& in, double res, int num_classes,
                         perception::LabelledCloud* out) {
  struct Entry {
    std::uint64_t cell;
    std::uint8_t label;
    std::uint32_t index;
  };
  out->clear();
  out->origin_world = in.origin_world;
  out->R_world_camera = in.R_world_camera;
  const Eigen::Matrix3d Rt = in.R_world_camera.transpose();
  constexpr std::int64_t kHalf = std::int64_t(1) << 20;
  std::vector<Entry> entries;
  entries.reserve(in.points_world.size());
  for (std::size_t i = 0; i < in.points_world.size(); ++i) {
    const Vec3f& p = in.points_world[i];
    bool ok = std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) && in.labels[i] < num_classes;
    std::uint64_t cell = 0;
    if (ok) {
      const Vec3 c = Rt * (p.cast<double>() - in.origin_world) / res;
      for (int a = 0; a < 3 && ok; ++a) {
        const double f = std::floor(c[a]);
        ok = f > double(-kHalf) && f < double(kHalf - 1);
        if (ok) cell |= std::uint64_t(std::int64_t(f) + kHalf) << (21 * a);
      }
    }
    if (!ok) {  // passed through as it is
      out->points_world.push_back(p);
      out->labels.push_back(in.labels[i]);
      continue;
    }
    entries.push_back({cell, in.labels[i], static_cast<std::uint32_t>(i)});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.cell != b.cell ? a.cell < b.cell : (a.label != b.label ? a.label < b.label : a.index < b.index);
  });
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    Vec3 sum = Vec3::Zero();
    int best_label = -1;
    std::size_t best_count = 0;
    while (j < entries.size() && entries[j].cell == entries[i].cell) {
      const std::uint8_t label = entries[j].label;
      std::size_t count = 0;
      for (; j < entries.size() && entries[j].cell == entries[i].cell && entries[j].label == label; ++j) {
        sum += in.points_world[entries[j].index].cast<double>();
        ++count;
      }
      if (count > best_count) {
        best_count = count;
        best_label = label;
      }
    }
    out->points_world.push_back((sum / double(j - i)).cast<float>());
    out->labels.push_back(static_cast<std::uint8_t>(best_label));
    i = j;
  }
}

bool all_finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Stage 1's view of the scan: the cloud, its origin, and the limits each point is held to.
struct PointCoding {
  const perception::LabelledCloud& cloud;
  Vec3f origin;
  double max_range2;
  double inv_res;
  int num_classes;
};

// Points stage 1 skipped or found beyond range, summed over its chunks.
struct PointCounts {
  std::atomic<std::size_t> bad_point{0}, bad_label{0}, outside{0}, beyond{0};
};

constexpr std::uint64_t kLow56 = (1ull << 56) - 1;
constexpr std::uint64_t kMaxRun = 254;  // so a value never equals kInvalid

// Stage 1 on the points of `r`: each point's (code << 8 | label) or, beyond range, its code
// with kBeyond; runs of equal values merged into one carrying the run length in its top byte
// (or added to the value an earlier run of the chunk wrote, while it fits), written from
// r.begin() on; the rest of the chunk kInvalid.
void code_point_chunk(const PointCoding& c, const tbb::blocked_range<std::size_t>& r,
                      std::vector<std::uint64_t>& values, PointCounts& counts) {
  std::size_t nb = 0, nl = 0, no = 0, nf = 0;
  std::size_t out = r.begin();  // write cursor within this chunk
  std::uint64_t run_value = kInvalid, run_length = 0;
  octomap::OcTreeKey last_key(0, 0, 0);
  std::uint64_t last_code = morton_code(last_key) << 8;
  // The rows of a chunk cross the same voxels again: a run whose value was written recently
  // (a direct-mapped table of values and where they went) adds its length there.
  constexpr int kSlotBits = 10;
  std::uint64_t slot_value[1 << kSlotBits];
  std::uint32_t slot_at[1 << kSlotBits];
  std::fill(std::begin(slot_value), std::end(slot_value), kInvalid);
  auto flush = [&] {
    if (!run_length) return;
    const std::size_t slot = std::size_t((run_value * 0x9E3779B97F4A7C15ull) >> (64 - kSlotBits));
    if (slot_value[slot] == run_value) {
      std::uint64_t& v = values[slot_at[slot]];
      if ((v >> 56) + run_length <= kMaxRun) {
        v += run_length << 56;
        run_length = 0;
        return;
      }
    }
    slot_value[slot] = run_value;
    slot_at[slot] = static_cast<std::uint32_t>(out);
    values[out++] = (run_length << 56) | run_value;
    run_length = 0;
  };
  for (std::size_t i = r.begin(); i != r.end(); ++i) {
    const Vec3f& p = c.cloud.points_world[i];
    const std::uint8_t label = c.cloud.labels[i];
    octomap::OcTreeKey key;
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      ++nb;
    } else if (label >= c.num_classes) {
      ++nl;
    } else if (!point_key(p, c.inv_res, &key)) {
      ++no;
    } else {
      const bool far = double((p - c.origin).squaredNorm()) > c.max_range2;
      nf += far;
      if (!(key == last_key)) {  // neighbouring pixels mostly share a voxel
        last_key = key;
        last_code = morton_code(key) << 8;
      }
      const std::uint64_t v = last_code | (far ? kBeyond : label);
      if (v == run_value && run_length < kMaxRun) {
        ++run_length;
      } else {
        flush();
        run_value = v;
        run_length = 1;
      }
    }
  }
  flush();
  for (std::size_t i = out; i != r.end(); ++i) values[i] = kInvalid;
  counts.bad_point += nb;
  counts.bad_label += nl;
  counts.outside += no;
  counts.beyond += nf;
}

// 1. Per point: key code and label, or kInvalid (bad input is counted). Neighbouring pixels
//    mostly fall in the same voxel, so each chunk merges runs of equal (code, label) into one
//    value carrying the run length in its top byte. Leaves the values sorted by (code, label).
void code_points(const PointCoding& c, std::size_t n, int threads, std::vector<std::uint64_t>* values,
                 std::vector<std::uint64_t>* scratch, InsertStats* stats) {
  values->resize(n);
  PointCounts counts;
  auto point_chunk = [&](const tbb::blocked_range<std::size_t>& r) { code_point_chunk(c, r, *values, counts); };
  // Threads pay only for large clouds: waking a worker costs about what 20k points do.
  if (n < kParallelPoints || threads == 1) {
    point_chunk(tbb::blocked_range<std::size_t>(0, n));
  } else {
    run_in_arena(threads, [&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), point_chunk);
    });
  }
  stats->bad_point = counts.bad_point;
  stats->bad_label = counts.bad_label;
  stats->outside_map = counts.outside;
  stats->beyond_range = counts.beyond;
  values->erase(std::remove(values->begin(), values->end(), kInvalid), values->end());
  radix_sort_u64(*values, *scratch, 56);  // by (code, label); run lengths ride along
}

// 2. Voxel filter: one ray target per voxel; a hit with the majority label when any point
//    in it is within range (ties go to the smaller class index).
//    per_endpoint: every point left by the camera-frame filter is a hit of its voxel: the
//    voxel's labels by count (most first, ties to the smaller class), each as often as it
//    was seen; the first goes with the free cells, the others into `extra` layers.
//    Returns the number of hit updates.
std::size_t voxel_targets(const std::vector<std::uint64_t>& values, bool per_endpoint, std::vector<VoxelUpdate>* hits,
                          std::vector<std::uint64_t>* ray_targets, std::vector<std::vector<VoxelUpdate>>* extra) {
  hits->clear();
  ray_targets->clear();
  std::size_t hit_updates = 0;
  std::vector<std::pair<std::uint64_t, std::uint8_t>> seen;  // (count, label) of one voxel
  for (std::size_t i = 0; i < values.size();) {
    const std::uint64_t code = (values[i] & kLow56) >> 8;
    int best_label = -1;
    std::uint64_t best_count = 0;
    std::size_t j = i;
    seen.clear();
    while (j < values.size() && ((values[j] & kLow56) >> 8) == code) {
      const std::uint64_t v = values[j] & kLow56;
      const std::uint8_t label = v & 0xff;
      std::uint64_t count = 0;
      for (; j < values.size() && (values[j] & kLow56) == v; ++j) count += values[j] >> 56;
      if (label != kBeyond && count > best_count) {
        best_count = count;
        best_label = label;
      }
      if (label != kBeyond) seen.emplace_back(count, label);
    }
    if (best_label >= 0) {
      hits->push_back({code, static_cast<std::uint8_t>(best_label)});
      ++hit_updates;
    }
    if (per_endpoint && best_label >= 0) {
      std::stable_sort(seen.begin(), seen.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      std::size_t layer = 0;
      for (const auto& [count, label] : seen)
        for (std::uint64_t c = (label == best_label ? 1 : 0); c < count; ++c) {
          if (extra->size() <= layer) extra->emplace_back();
          (*extra)[layer++].push_back({code, label});
          ++hit_updates;
        }
    }
    ray_targets->push_back(best_label >= 0 ? code : (code | kBeyondFlag));
    i = j;
  }
  return hit_updates;
}

// How many threads share a scan's rays (their segments, then marking them, one grid each):
// those asked for (0: all), never more than the calling arena can run at once (the grids cost
// a box's bits each).
int ray_threads(int threads, std::size_t rays) {
  if (rays < kParallelRays || threads == 1) return 1;
  const int available = std::max(1, tbb::this_task_arena::max_concurrency());
  return threads > 1 ? std::min(threads, available) : available;
}

// Stage 3's first step: the segment of every ray target, and the box of keys holding the
// origin and every segment's end, with one cell to spare on each side. Large scans split the
// segments between threads (each segment is its own; the box is the bounds' union).
KeyBitGrid ray_segments(const SemanticOcTree& map, const SemanticMapParams& P, const octomap::OcTreeKey& origin_key,
                        const octomap::point3d& origin, const std::vector<std::uint64_t>& ray_targets,
                        std::vector<RaySegment>* segments) {
  segments->resize(ray_targets.size());
  struct Bounds {
    int lo[3], hi[3];
  };
  auto part = [&](std::size_t r0, std::size_t r1, Bounds* b) {
    for (int a = 0; a < 3; ++a) b->lo[a] = b->hi[a] = origin_key[a];
    for (std::size_t r = r0; r < r1; ++r) {
      (*segments)[r] = ray_segment(map, origin, ray_targets[r], P.ray_range_m, P.max_range_m);
      octomap::OcTreeKey ke;
      if (!map.coordToKeyChecked((*segments)[r].end, ke)) continue;
      for (int a = 0; a < 3; ++a) {
        b->lo[a] = std::min(b->lo[a], int(ke[a]));
        b->hi[a] = std::max(b->hi[a], int(ke[a]));
      }
    }
  };
  const std::size_t n = ray_targets.size();
  const int parts = ray_threads(P.threads, n);
  std::vector<Bounds> bounds(static_cast<std::size_t>(parts));
  if (parts == 1) {
    part(0, n, &bounds[0]);
  } else {
    run_in_arena(parts, [&] {
      tbb::parallel_for(0, parts, [&](int k) {
        const std::size_t q = std::size_t(k), m = std::size_t(parts);
        part(n * q / m, n * (q + 1) / m, &bounds[q]);
      });
    });
  }
  KeyBitGrid box;  // its cells come later
  for (int a = 0; a < 3; ++a) {
    int lo = bounds[0].lo[a], hi = bounds[0].hi[a];
    for (const Bounds& b : bounds) lo = std::min(lo, b.lo[a]), hi = std::max(hi, b.hi[a]);
    box.lo[a] = lo - 1;
    box.n[a] = hi - lo + 3;
  }
  return box;
}

// The box's grid in `words`.
KeyBitGrid over(KeyBitGrid box, std::uint64_t* words) {
  box.words = words;
  return box;
}

// Marks every cell the rays cross, one bit per cell of the box, in grid t of `planes` (`size`
// words each) for the thread in slot t: no cache line is written by two threads.
void mark_rays(const SemanticOcTree& map, const KeyBitGrid& box, const std::vector<RaySegment>& segments, int planes,
               bool vectorised, std::uint64_t* grids, std::size_t size) {
  auto mark = [&](const RaySegment* chunk, std::size_t n, std::uint64_t* grid) {
    mark_walked_voxels(
        map, n,
        [chunk](std::size_t i, octomap::point3d* a, octomap::point3d* b) {
          *a = chunk[i].origin;
          *b = chunk[i].end;
        },
        over(box, grid), vectorised);
  };
  if (planes == 1) {
    mark(segments.data(), segments.size(), grids);
    return;
  }
  tbb::task_arena arena(planes);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, segments.size(), 256), [&](const auto& r) {
      const int slot = tbb::this_task_arena::current_thread_index();
      CANOPY_CHECK(slot >= 0 && slot < planes, "ray marking: thread slot " << slot << " of " << planes);
      mark(segments.data() + r.begin(), r.size(), grids + std::size_t(slot) * size);
    });
  });
}

// The free cells (marked in a grid, not hit) among the cells of words [w0, w1), in order, into
// `out`; clears those words of the grids and of the hits.
void collect_cells(const KeyBitGrid& box, int planes, std::size_t size, std::uint64_t* grids, std::uint64_t* hit,
                   std::size_t w0, std::size_t w1, std::vector<std::uint64_t>& out) {
  const std::size_t nx = std::size_t(box.n[0]), nxy = nx * std::size_t(box.n[1]);
  for (std::size_t w = w0; w < w1; ++w) {
    std::uint64_t m = 0;
    for (int p = 0; p < planes; ++p) {
      std::uint64_t& g = grids[std::size_t(p) * size + w];
      m |= g;
      g = 0;
    }
    m &= ~hit[w];
    hit[w] = 0;
    while (m) {
      const std::size_t i = w * 64 + std::size_t(__builtin_ctzll(m));
      m &= m - 1;
      const std::size_t z = i / nxy, r = i % nxy, y = r / nx, x = r % nx;
      out.push_back(morton_code(octomap::OcTreeKey(static_cast<octomap::key_type>(box.lo[0] + int(x)),
                                                   static_cast<octomap::key_type>(box.lo[1] + int(y)),
                                                   static_cast<octomap::key_type>(box.lo[2] + int(z)))));
    }
  }
}

// The free cells as sorted codes, collected over ranges of words (in order, so the result
// does not depend on threads); leaves the grids and the hits cleared.
void collect_free(const KeyBitGrid& box, int threads, int planes, std::uint64_t* grids, std::uint64_t* hit,
                  std::vector<std::vector<std::uint64_t>>* slices, std::vector<std::uint64_t>* free_codes,
                  std::vector<std::uint64_t>* scratch) {
  constexpr std::size_t kWordsPerRange = std::size_t(1) << 10;
  const std::size_t size = box.word_count(), ranges = (size + kWordsPerRange - 1) / kWordsPerRange;
  if (slices->size() < ranges) slices->resize(ranges);
  for (auto& sl : *slices) sl.clear();
  const std::size_t grain = box.size() < kParallelCells || threads == 1 ? ranges + 1 : 1;
  run_in_arena(threads, [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ranges, grain), [&](const auto& r) {
      for (std::size_t k = r.begin(); k != r.end(); ++k)
        collect_cells(box, planes, size, grids, hit, k * kWordsPerRange, std::min(size, (k + 1) * kWordsPerRange),
                      (*slices)[k]);
    });
  });
  for (std::size_t k = 0; k < ranges; ++k) free_codes->insert(free_codes->end(), (*slices)[k].begin(), (*slices)[k].end());
  radix_sort_u64(*free_codes, *scratch, 48);
}

// Rays too long for a dense grid: collect, sort and de-duplicate the keys, then drop the hits.
void free_by_sorting(const SemanticOcTree& map, const std::vector<RaySegment>& segments,
                     const std::vector<VoxelUpdate>& hits, std::vector<std::uint64_t>* free_codes,
                     std::vector<std::uint64_t>* scratch) {
  for (const Segment& s : segments)
    traverse(map, s, [&](const octomap::OcTreeKey& k) { free_codes->push_back(morton_code(k)); });
  radix_sort_u64(*free_codes, *scratch, 48);
  free_codes->erase(std::unique(free_codes->begin(), free_codes->end()), free_codes->end());
  std::size_t w = 0, h = 0;
  for (const std::uint64_t c : *free_codes) {
    while (h < hits.size() && hits[h].code < c) ++h;
    if (h < hits.size() && hits[h].code == c) continue;
    (*free_codes)[w++] = c;
  }
  free_codes->resize(w);
}

// 4. Merges hits and free cells (both sorted) into one sorted batch.
void merge_updates(const std::vector<VoxelUpdate>& hits, const std::vector<std::uint64_t>& free_codes,
                   std::vector<VoxelUpdate>* updates) {
  updates->reserve(hits.size() + free_codes.size());
  std::size_t h = 0;
  for (const std::uint64_t c : free_codes) {
    while (h < hits.size() && hits[h].code < c) updates->push_back(hits[h++]);
    updates->push_back({c, VoxelUpdate::kFree});
  }
  while (h < hits.size()) updates->push_back(hits[h++]);
}

}  // namespace

bool ray_free_keys(const SemanticOcTree& map, const Vec3& origin, const Vec3& end, std::vector<octomap::OcTreeKey>* keys) {
  octomap::KeyRay ray;
  const octomap::point3d o(float(origin.x()), float(origin.y()), float(origin.z()));
  const octomap::point3d e(float(end.x()), float(end.y()), float(end.z()));
  if (!map.computeRayKeys(o, e, ray)) return false;
  keys->insert(keys->end(), ray.begin(), ray.end());
  return true;
}

ScanInserter::ScanInserter(SemanticOcTree& map) : map_(map) {}

void ScanInserter::compute_updates(const perception::LabelledCloud& input, std::vector<VoxelUpdate>* updates,
                                   InsertStats* stats) {
  const SemanticMapParams& P = map_.params();
  const int num_classes = map_.num_classes();
  CANOPY_CHECK(input.labels.size() == input.points_world.size(),
               "cloud has " << input.points_world.size() << " points but " << input.labels.size() << " labels");
  stats->points = input.points_world.size();
  updates->clear();
  for (auto& layer : extra_) layer.clear();
  const bool per_endpoint = P.insertion == Insertion::kPerEndpoint;
  if (per_endpoint && all_finite(input.origin_world))
    camera_voxel_filter(input, map_.getResolution(), num_classes, &filtered_);
  const perception::LabelledCloud& cloud = per_endpoint ? filtered_ : input;
  const std::size_t n = per_endpoint ? cloud.points_world.size() : input.points_world.size();
  if ((per_endpoint && !all_finite(input.origin_world)) || !all_finite(cloud.origin_world)) {
    stats->bad_point = stats->points;
    return;
  }
  octomap::OcTreeKey origin_key;
  if (!map_.key_of(cloud.origin_world, &origin_key)) {
    stats->outside_map = stats->points;
    return;
  }
  const Stopwatch t0;
  const Vec3f o = cloud.origin_world.cast<float>();
  const PointCoding coding{cloud, o, P.max_range_m * P.max_range_m, 1.0 / map_.getResolution(), num_classes};
  code_points(coding, n, P.threads, &values_, &scratch_, stats);
  const std::size_t hit_updates = voxel_targets(values_, per_endpoint, &hits_, &ray_targets_, &extra_);
  stats->rays = ray_targets_.size();
  stats->hit_voxels = hits_.size();
  stats->hit_updates = hit_updates;
  stats->ms_filter = t0.ms();
  const Stopwatch t1;

  // 3. Free space: mark the cells of every ray in bit grids over the rays' box (one per
  //    thread), then collect the cells marked in any grid and not hit in this scan.
  const octomap::point3d origin(o.x(), o.y(), o.z());
  // segments_ is reused: large vectors would be mmap'ed anew
  const KeyBitGrid box = ray_segments(map_, P, origin_key, origin, ray_targets_, &segments_);
  free_codes_.clear();
  if (box.size() <= kMaxGridCells) {
    const std::size_t size = box.word_count();
    const int planes = ray_threads(P.threads, segments_.size());
    // Both stay cleared between scans (collect_free clears what it used).
    if (crossed_.size() < std::size_t(planes) * size) crossed_.assign(std::size_t(planes) * size, 0);
    if (hit_cells_.size() < size) hit_cells_.assign(size, 0);
    const KeyBitGrid hit = over(box, hit_cells_.data());
    for (const VoxelUpdate& h : hits_) {
      const octomap::OcTreeKey k = morton_key(h.code);
      hit(k[0], k[1], k[2]);
    }
    try {
      mark_rays(map_, box, segments_, planes, vectorised_, crossed_.data(), size);
      collect_free(box, P.threads, planes, crossed_.data(), hit_cells_.data(), &slices_, &free_codes_, &scratch_);
    } catch (...) {  // leave the grids cleared for the next scan
      std::fill(crossed_.begin(), crossed_.begin() + std::ptrdiff_t(std::size_t(planes) * size), std::uint64_t(0));
      std::fill(hit_cells_.begin(), hit_cells_.begin() + std::ptrdiff_t(size), std::uint64_t(0));
      throw;
    }
  } else {
    free_by_sorting(map_, segments_, hits_, &free_codes_, &scratch_);
  }
  stats->free_voxels = free_codes_.size();

  merge_updates(hits_, free_codes_, updates);
  stats->ms_raycast = t1.ms();
}

InsertStats ScanInserter::insert(const perception::LabelledCloud& cloud) {
  const Stopwatch t0;
  InsertStats stats;
  compute_updates(cloud, &updates_, &stats);
  const Stopwatch t1;
  stats.tree = map_.apply_sorted_updates(updates_, &occupancy_);
  for (const std::vector<VoxelUpdate>& layer : extra_) {
    if (layer.empty()) continue;
    const UpdateCounts c = map_.apply_sorted_updates(layer, &layer_occupancy_);
    // A layer's voxels are among the first batch's (both sorted): their state after it is the
    // state after the scan.
    std::size_t i = 0;
    for (std::size_t k = 0; k < layer.size(); ++k) {
      while (updates_[i].code < layer[k].code) ++i;
      occupancy_[i] = static_cast<std::uint8_t>((occupancy_[i] & SemanticOcTree::kOccupiedBefore) |
                                                (layer_occupancy_[k] & SemanticOcTree::kOccupiedAfter));
    }
    stats.tree.applied += c.applied;
    stats.tree.saturated += c.saturated;
    stats.tree.created += c.created;
    stats.tree.pruned += c.pruned;
  }
  stats.ms_update = t1.ms();
  stats.ms_total = t0.ms();
  return stats;
}

}  // namespace canopy::mapping
