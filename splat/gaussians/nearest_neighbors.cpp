#include "splat/gaussians/nearest_neighbors.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// Most points per leaf (leaves hold between half this and this). Scanning a contiguous leaf
// is cheap next to descending the tree; 32 measured fastest of 8–32 on 100k points.
constexpr std::size_t kLeafSize = 32;
// The best-k list lives on the stack; 16 is far above what initialisation asks for (3).
constexpr int kMaxNeighbours = 16;
// Subtrees at least this large are built on separate tasks (disjoint index ranges, so the
// tree is the same whichever thread builds what).
constexpr std::size_t kParallelBuildSize = 16384;
// Queries per task.
constexpr std::size_t kQueriesPerTask = 1024;

// A point with its index in the caller's array, kept together so partitioning moves both.
struct Point {
  float x[3];
  std::uint32_t index;
};

// Interior nodes split [lo, hi) at mid = (lo + hi) / 2: points before mid have
// coordinate[axis] ≤ split, points from mid on have coordinate[axis] ≥ split. Nodes are
// numbered as a heap (children of i are 2i+1 and 2i+2); a range of at most kLeafSize
// points is a leaf, so the tree's shape follows from P alone.
struct Node {
  float split = 0;
  int axis = 0;
};

struct Tree {
  std::vector<Point> points;  // [P] in tree order: every leaf is a contiguous run
  std::vector<Node> nodes;
};

std::size_t node_count_for(std::size_t n) {
  // Heap indices reach below 2^(depth+1), where depth halvings bring the largest range
  // (which rounds up) down to a leaf.
  std::size_t levels = 1, largest = n;
  while (largest > kLeafSize) {
    largest = (largest + 1) / 2;
    ++levels;
  }
  return (std::size_t(1) << levels);
}

void build(Tree& tree, std::size_t node, std::size_t lo, std::size_t hi) {
  if (hi - lo <= kLeafSize) return;
  std::vector<Point>& pts = tree.points;
  // Widest axis of the range's bounding box: keeps cells compact for clustered clouds.
  float low[3], high[3];
  for (int a = 0; a < 3; ++a) low[a] = high[a] = pts[lo].x[a];
  for (std::size_t i = lo + 1; i < hi; ++i)
    for (int a = 0; a < 3; ++a) {
      low[a] = std::min(low[a], pts[i].x[a]);
      high[a] = std::max(high[a], pts[i].x[a]);
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (high[a] - low[a] > high[axis] - low[axis]) axis = a;

  const std::size_t mid = (lo + hi) / 2;
  std::nth_element(pts.begin() + lo, pts.begin() + mid, pts.begin() + hi,
                   [axis](const Point& a, const Point& b) {
                     // Ties broken by index so the partition is a pure function of the input.
                     return a.x[axis] < b.x[axis] || (a.x[axis] == b.x[axis] && a.index < b.index);
                   });
  tree.nodes[node] = {pts[mid].x[axis], axis};

  auto left = [&] { build(tree, 2 * node + 1, lo, mid); };
  auto right = [&] { build(tree, 2 * node + 2, mid, hi); };
  if (hi - lo >= kParallelBuildSize)
    tbb::parallel_invoke(left, right);
  else {
    left();
    right();
  }
}

// The k smallest squared distances seen so far, ascending, with their tree positions.
struct BestList {
  explicit BestList(int k_) : k(k_) {}

  int k;
  int count = 0;
  std::array<float, kMaxNeighbours> distance{};
  std::array<std::uint32_t, kMaxNeighbours> position{};

  float worst() const {
    return count < k ? std::numeric_limits<float>::infinity() : distance[k - 1];
  }
  void offer(float d, std::uint32_t pos) {
    if (d >= worst()) return;  // only strictly closer points change the distances
    int i = count < k ? count++ : k - 1;
    while (i > 0 && distance[i - 1] > d) {
      distance[i] = distance[i - 1];
      position[i] = position[i - 1];
      --i;
    }
    distance[i] = d;
    position[i] = pos;
  }
};

void search(const Tree& tree, std::size_t node, std::size_t lo, std::size_t hi,
            std::size_t self, const Point& q, BestList& best) {
  if (hi - lo <= kLeafSize) {
    for (std::size_t i = lo; i < hi; ++i) {
      if (i == self) continue;
      const Point& p = tree.points[i];
      const float dx = p.x[0] - q.x[0], dy = p.x[1] - q.x[1], dz = p.x[2] - q.x[2];
      best.offer(dx * dx + dy * dy + dz * dz, std::uint32_t(i));
    }
    return;
  }
  const Node& n = tree.nodes[node];
  const std::size_t mid = (lo + hi) / 2;
  const float diff = q.x[n.axis] - n.split;
  const bool left_first = diff < 0;
  if (left_first)
    search(tree, 2 * node + 1, lo, mid, self, q, best);
  else
    search(tree, 2 * node + 2, mid, hi, self, q, best);
  // Every point across the plane is at least |diff| away along this axis (rounding is
  // monotone, so this holds for the float distances too).
  if (diff * diff < best.worst()) {
    if (left_first)
      search(tree, 2 * node + 2, mid, hi, self, q, best);
    else
      search(tree, 2 * node + 1, lo, mid, self, q, best);
  }
}

}  // namespace

std::vector<float> mean_squared_neighbour_distance(const std::vector<float>& positions, int k,
                                                   std::vector<std::uint32_t>* neighbours) {
  if (k < 1 || k > kMaxNeighbours)
    throw ArgumentError("mean_squared_neighbour_distance: k = " + std::to_string(k) +
                        " is outside 1.." + std::to_string(kMaxNeighbours));
  if (positions.size() % 3 != 0)
    throw ArgumentError("mean_squared_neighbour_distance: " + std::to_string(positions.size()) +
                        " coordinates is not a multiple of 3");
  const std::size_t n = positions.size() / 3;

  Tree tree;
  tree.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    tree.points[i] = {{positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]},
                      std::uint32_t(i)};
  }
  tree.nodes.resize(node_count_for(n));
  if (n > 0) build(tree, 0, 0, n);

  std::vector<float> mean(n);
  if (neighbours) neighbours->assign(n * std::size_t(k), kNoNeighbour);
  // Queries in tree order: consecutive queries touch the same leaves.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kQueriesPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        BestList best(k);
                        search(tree, 0, 0, n, i, tree.points[i], best);
                        float sum = 0;
                        for (int j = 0; j < best.count; ++j) sum += best.distance[j];
                        const std::uint32_t original = tree.points[i].index;
                        mean[original] = best.count > 0 ? sum / float(best.count) : 0.0f;
                        if (neighbours)
                          for (int j = 0; j < best.count; ++j)
                            (*neighbours)[std::size_t(original) * k + j] =
                                tree.points[best.position[j]].index;
                      }
                    });
  return mean;
}

}  // namespace splat
