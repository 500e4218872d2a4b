#pragma once
// A KD-tree over 3D points (nanoflann), shared by the coverage metric, fruit clustering and
// the workspace filter.

#include <nanoflann.hpp>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "canopy/common/types.h"

namespace canopy {

/// Owns its points and a nanoflann index over them. Not copyable or movable (the index
/// points into the tree's own storage); hold it in a unique_ptr to pass it around.
class PointKdTree {
 public:
  explicit PointKdTree(std::vector<Vec3> points, int leaf_size = 10)
      : points_(std::move(points)), adaptor_{&points_},
        tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<size_t>(leaf_size))) {
    tree_.buildIndex();
  }
  PointKdTree(const PointKdTree&) = delete;
  PointKdTree& operator=(const PointKdTree&) = delete;

  const std::vector<Vec3>& points() const { return points_; }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }

  /// Nearest point to `q`: its index and squared distance; false when the tree is empty.
  bool nearest(const Vec3& q, std::size_t* index, double* dist2) const {
    if (points_.empty()) return false;
    std::size_t i = 0;
    double d2 = 0.0;
    if (tree_.knnSearch(q.data(), 1, &i, &d2) != 1) return false;
    *index = i;
    *dist2 = d2;
    return true;
  }
  /// Indices of the points within `radius` of `q`, nearest first (replaces `out`).
  void within(const Vec3& q, double radius, std::vector<std::pair<std::size_t, double>>* out) const {
    out->clear();
    if (points_.empty()) return;
    tree_.radiusSearch(q.data(), radius * radius, *out, nanoflann::SearchParams());
  }

 private:
  struct Adaptor {
    const std::vector<Vec3>* pts;
    std::size_t kdtree_get_point_count() const { return pts->size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*pts)[i][static_cast<int>(dim)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3, std::size_t>;

  std::vector<Vec3> points_;
  Adaptor adaptor_;
  Tree tree_;
};

}  // namespace canopy
