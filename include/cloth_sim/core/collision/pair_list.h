/// @file pair_list.h
/// A list of the self-contact pairs near each other that serves the substeps after it while the
/// cloth moves little (Verlet's neighbour list, kept per vertex; docs/method.md, "Self-contact").
#pragma once

#include <vector>

#include "cloth_sim/core/collision/pair_search.h"
#include "cloth_sim/core/collision/surface_topology.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The candidate pairs of each substep from a list kept between substeps.
///
/// Each vertex i has an anchor a_i (m). The list holds every vertex-triangle pair whose
/// primitives, placed at the anchors, are within r + 2 m of each other, and every edge pair
/// within r_e + 2 m (r, r_e: the reaches of PairSearch::find; m: the margin), measured exactly
/// (closest points), but for the pairs within patches flat enough to stay flat
/// (PairSearch::findTouching). While every vertex's path over a substep stays within m of its
/// anchor, every point of a primitive stays within m of its place at the anchors (a convex
/// combination of its vertices), so a pair missing from the list stays farther apart than its
/// reach over the whole substep, or within a flat patch, which the search skips too: the list,
/// filtered by each pair's distance at the anchors less how far its vertices are from theirs
/// and by the substep's boxes (the tests PairSearch ends with), holds every pair the search's
/// callers need, those that come within the reach.
///
/// A vertex whose path leaves its anchor's ball is anchored again at its path's midpoint (when
/// the path is at most 2 m long) and its pairs are listed again; more than a quarter of the
/// vertices at once, or none yet, and the whole list is made again. A substep in which a vertex
/// moves more than 2 m is searched over its paths (PairSearch::find) and leaves the list as it
/// is. The list's order depends only on the positions, so a run is the same on any number of
/// threads.
class PairList {
 public:
  /// @p tree: a PairSearch of the cloth, which the list keeps as its own (its boxes and normals
  /// stay at the anchors between substeps); @p margin: m (m, > 0).
  PairList(const PairSearch& tree, double margin);

  /// Fills @p out with the pairs of the motion @p start -> @p end (m) that come within @p reach
  /// (vertex-triangle) or @p edge_reach (edge pairs) (m, as PairSearch::find), or more.
  /// Returns whether the list served (false: @p search searched the paths).
  bool find(PairSearch& search, const SurfaceTopology& topology, const Points& start,
            const Points& end, double reach, double edge_reach, std::vector<PairCandidate>& out);

  /// Threads of the list's tree walks (the same list on any number).
  void setThreads(int threads) { tree_.setThreads(threads); }
  /// Pairs in the list.
  std::size_t size() const { return listed_.size(); }
  /// Vertices anchored again by the last find that served (all of them when it made the list).
  int anchored() const { return anchored_; }

 private:
  /// Lists again the pairs with a vertex in touched_ (all when @p all), at the anchors.
  void relist(const SurfaceTopology& topology, double reach, double edge_reach, bool all);
  /// Appends to @p out the listed pairs that may come within the reaches over start -> end:
  /// their distance at the anchors less how far their vertices are from them, and their path
  /// boxes.
  void filter(const Points& start, const Points& end, double reach, double edge_reach,
              std::vector<PairCandidate>& out);

  PairSearch tree_;  ///< at the anchors
  double margin_;
  double reach_ = -1.0, edge_reach_ = -1.0;  ///< of the list
  int anchored_ = 0;
  Points anchor_;                          ///< a_i (m); empty: no list yet
  /// A listed pair and its distance at the anchors (m).
  struct Listed {
    PairCandidate pair;
    double distance;
  };
  std::vector<Listed> listed_;
  std::vector<PairCandidate> found_;
  std::vector<double> away_;               ///< each vertex's farthest from its anchor (m)
  std::vector<char> touched_;              ///< vertices anchored again in this find
  Points lo_, hi_;                         ///< each vertex's path box in this find (m)
};

}  // namespace cloth_sim
