// Triangle self-contact (triangle_self_contact.h) on two small sheets of one mesh: a sheet
// thrown through another within one substep stops at the thickness, edges crossing edges are
// caught, momentum is kept, pins and friction are respected, the impact stage's fail-safe and
// the untangling of sheets that already cross.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/impact_failsafe.h"
#include "cloth_sim/core/collision/triangle_intersection.h"
#include "cloth_sim/core/collision/triangle_self_contact.h"
#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

/// Two n x n sheets of side @p size in one mesh (vertices 0 .. n^2 - 1 the lower one), the upper
/// one @p lift above the lower one and shifted by @p shift in x and y.
struct TwoSheets {
  Eigen::Matrix3Xi triangles;
  Points rest;
  int n2 = 0;
  TwoSheets(int n, double size, double lift, double shift) {
    GridSpec spec;
    spec.rows = spec.cols = n;
    spec.width = spec.height = size;
    const BuiltObject g = buildGrid(spec);
    n2 = n * n;
    const Eigen::Index t = g.model.triangles.cols();
    triangles.resize(3, 2 * t);
    triangles << g.model.triangles, (g.model.triangles.array() + n2).matrix();
    rest.resize(3, 2 * n2);
    rest << g.rest_positions, (g.rest_positions.colwise() + Vec3(shift, shift, lift));
  }
};

struct StepData {
  Eigen::VectorXd mass;
  std::vector<char> movable;
  Points start;
  StepData(const Points& s) : mass(Eigen::VectorXd::Constant(s.cols(), 0.01)), movable(s.cols(), 1), start(s) {}
  CollisionStep step(double h) const { return CollisionStep{h, mass, movable, start}; }
};

TEST(TriangleSelfContact, SheetThrownThroughAnotherStopsAtTheThickness) {
  const double t = 0.002;
  const TwoSheets s(6, 0.1, 0.01, 0.013);  // the upper sheet 1 cm above, shifted off the grid
  TriangleSelfContact contact(s.triangles, s.rest, t, 0.0);
  StepData data(s.rest);
  Points end = s.rest, v = Points::Zero(3, s.rest.cols());
  for (int i = s.n2; i < 2 * s.n2; ++i) end(2, i) -= 0.05;  // 5 cm down in one substep
  const Vec3 momentum = (end - s.rest).rowwise().sum();
  contact.resolve(data.step(0.002), GroundPlane{}, end, v);
  IntersectionCounter counter(s.triangles);
  EXPECT_EQ(counter.count(end), 0);
  const TriangleContactStats& st = contact.lastStats();
  std::printf("thrown: %ld triangle pairs, %ld candidates, %ld proximity, %ld impacts\n",
              st.triangle_pairs, st.candidates, st.proximity, st.impacts);
  EXPECT_GT(st.proximity, 0);
  // Equal masses share every push, so the momentum stays.
  EXPECT_LT(((end - s.rest).rowwise().sum() - momentum).norm(), 1e-12);
  // One plunge of 5 cm = 25 t leaves the sheets apart, and the next substeps' proximity stage
  // restores the thickness between them.
  EXPECT_GE(contact.minPairDistance(end, 0.01), 0.1 * t);
  Points still = end;
  for (int k = 0; k < 4; ++k) {
    StepData rest_step(still);
    contact.resolve(rest_step.step(0.002), GroundPlane{}, still, v);
    EXPECT_EQ(counter.count(still), 0);
  }
  EXPECT_GE(contact.minPairDistance(still, 0.01), 0.9 * t);
  // Velocities follow the positions' change over h.
  EXPECT_GT(v.block(2, s.n2, 1, s.n2).maxCoeff(), 1.0);
}

TEST(TriangleSelfContact, PinnedSheetIsNotPushedAndTheOtherRestsOnIt) {
  const double t = 0.003;
  const TwoSheets s(5, 0.1, 0.004, 0.0);
  TriangleSelfContact contact(s.triangles, s.rest, t, 0.3);
  StepData data(s.rest);
  for (int i = 0; i < s.n2; ++i) data.movable[i] = 0;
  Points end = s.rest, v = Points::Zero(3, s.rest.cols());
  for (int i = s.n2; i < 2 * s.n2; ++i) end(2, i) -= 0.006;  // 2 mm below the lower sheet
  contact.resolve(data.step(0.002), GroundPlane{}, end, v);
  for (int i = 0; i < s.n2; ++i) EXPECT_EQ(end.col(i), s.rest.col(i));
  for (int i = s.n2; i < 2 * s.n2; ++i) EXPECT_NEAR(end(2, i), t, 1e-9) << i;
}

TEST(TriangleSelfContact, FrictionCutsTheSlide) {
  const double t = 0.003;
  for (const double mu : {0.0, 1.0}) {
    const TwoSheets s(5, 0.1, 0.003, 0.0);
    TriangleSelfContact contact(s.triangles, s.rest, t, mu);
    StepData data(s.rest);
    for (int i = 0; i < s.n2; ++i) data.movable[i] = 0;
    Points end = s.rest, v = Points::Zero(3, s.rest.cols());
    // The upper sheet slides 1 mm and is pushed 2 mm into the lower one.
    for (int i = s.n2; i < 2 * s.n2; ++i) end.col(i) += Vec3(0.001, 0.0, -0.002);
    contact.resolve(data.step(0.002), GroundPlane{}, end, v);
    const double slide = (end.col(2 * s.n2 - 1) - s.rest.col(2 * s.n2 - 1)).x();
    if (mu == 0.0) {
      EXPECT_NEAR(slide, 0.001, 1e-9);
    } else {
      EXPECT_NEAR(slide, 0.0, 1e-9);  // 2 mm of push holds 1 mm of slide
    }
  }
}

TEST(TriangleSelfContact, EdgeDrivenThroughAnEdgeIsStopped) {
  // Two long thin triangles crossing as an X, one above the other: the upper one's long edge is
  // pulled down through the lower one's long edge while no vertex passes over a face.
  Eigen::Matrix3Xi tri(3, 2);
  tri << 0, 3, 1, 4, 2, 5;
  Points rest(3, 6);
  rest << -1, 1, 1, 0, 0.02, -0.02,  //
      0, 0.02, -0.02, -1, 1, 1,      //
      0, 0, 0, 0.01, 0.01, 0.01;
  // Upper triangle (3, 4, 5): along y at z = 0.01; lower (0, 1, 2): along x at z = 0.
  TriangleSelfContact contact(tri, rest, 0.001, 0.0);
  StepData data(rest);
  Points end = rest, v = Points::Zero(3, 6);
  for (int i = 3; i < 6; ++i) end(2, i) -= 0.02;
  contact.resolve(data.step(0.002), GroundPlane{}, end, v);
  IntersectionCounter counter(tri);
  EXPECT_EQ(counter.count(end), 0);
  // Where the long edges cross in plan, the upper ones stay above the lower ones.
  for (const int upper : {4, 5}) {
    for (const int lower : {1, 2}) {
      const ClosestPoints cp = segmentSegment(end.col(3), end.col(upper), end.col(0), end.col(lower));
      EXPECT_GT(gapVector(cp, end.col(3), end.col(upper), end.col(0), end.col(lower)).z(), 0.0);
    }
  }
}

TEST(PairSearch, AQuadFoldedOverItsDiagonalIsListed) {
  // A flat grid with one quad folded over one of its triangles' edges: the far particle of the
  // triangle across the edge pushed down through the triangle, halfway to its centre and at it.
  // The rest of the cloth stays flat, so a patch that holds the particle's owner triangle and
  // the other one (joined at a vertex) looks flat when the folded triangle between them is not
  // in it; the pair must be listed for the impact stage all the same. Measured with the leaves'
  // own normals only: 384 of the 1,364 not listed (the pin jump of the untangling test at
  // 32 x 32 ended crossed so); with their rings' normals: none.
  GridSpec spec;
  spec.rows = spec.cols = 12;
  spec.width = spec.height = 0.33;
  const BuiltObject g = buildGrid(spec);
  const Eigen::Matrix3Xi& tri = g.model.triangles;
  const int n = static_cast<int>(g.rest_positions.cols());
  SurfaceTopology topology(tri, n);
  PairSearch search(topology, g.rest_positions);
  const double t = 0.001;
  const Vec3 up = Vec3::UnitZ();  // the grid's normal
  int cases = 0, missed = 0;
  std::vector<PairCandidate> pairs;
  for (int v = 0; v < n; ++v) {
    for (int k = 0; k < tri.cols(); ++k) {
      if (topology.triangleHas(k, v)) continue;
      int hinge = -1;  // v is the far corner of the triangle across k's side hinge .. hinge + 1
      for (int a = 0; a < 3; ++a) {
        const auto& faces = topology.edgeFaces(topology.findEdge(tri(a, k), tri((a + 1) % 3, k)));
        const int other = faces[0] == k ? faces[1] : faces[0];
        if (other >= 0 && topology.triangleHas(other, v)) hinge = a;
      }
      if (hinge < 0) continue;
      const Points& x = g.rest_positions;
      const Vec3 centre = (x.col(tri(0, k)) + x.col(tri(1, k)) + x.col(tri(2, k))) / 3.0;
      const Vec3 middle = 0.5 * (x.col(tri(hinge, k)) + x.col(tri((hinge + 1) % 3, k)));
      for (const double depth : {0.5, 1.0}) {  // folded on over the hinge: from its middle
        const Vec3 through = middle + depth * (centre - middle);  // towards the centre
        Points start = x, end = x;
        start.col(v) = through + 0.5 * t * up;
        end.col(v) = through - 0.5 * t * up;
        search.find(topology, start, end, 1.25 * t, 0.8 * t, pairs);
        bool listed = false;
        for (const PairCandidate& p : pairs) {
          listed = listed || (p.kind == PairKind::kVertexTriangle && p.v[0] == v &&
                              topology.triangleHas(k, p.v[1]) && topology.triangleHas(k, p.v[2]) &&
                              topology.triangleHas(k, p.v[3]));
        }
        ++cases;
        if (!listed) {
          ++missed;
          ADD_FAILURE() << "vertex " << v << " through triangle " << k << " (" << depth
                        << " of the way to its centre) not listed";
        }
      }
    }
  }
  std::printf("%d quads folded over, %d vertex-triangle pairs not listed\n", cases, missed);
  EXPECT_GT(cases, 1000);
}

TEST(PairSearch, ListsTheSamePairsInTheSameOrderOnAnyNumberOfThreads) {
  // A 1 m, 40 x 40 sheet folded in two across its middle, the upper half waved 2-6 mm above the lower
  // one (so no patch of it is flat with the other), moving a little over the substep (seeded):
  // the walk cut into jobs on 2 or 3 threads lists exactly the pairs of the serial walk, in its
  // order.
  GridSpec spec;
  spec.rows = spec.cols = 40;
  spec.width = spec.height = 1.0;
  const BuiltObject g = buildGrid(spec);
  const int n = static_cast<int>(g.rest_positions.cols());
  SurfaceTopology topology(g.model.triangles, n);
  PairSearch search(topology, g.rest_positions);
  Points start = g.rest_positions;
  const double middle = 0.5 * (start.row(0).minCoeff() + start.row(0).maxCoeff());
  for (int i = 0; i < n; ++i) {
    const double x = start(0, i), y = start(1, i);
    if (x > middle) {
      start(0, i) = 2.0 * middle - x;
      start(2, i) = 0.004 + 0.002 * std::sin(40.0 * x) * std::cos(30.0 * y);
    }
  }
  const unsigned seed = 20261127;
  std::printf("seed %u\n", seed);
  std::srand(seed);
  Points end = start;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) end(k, i) += 0.001 * (std::rand() / double(RAND_MAX) - 0.5);
  }
  const double t = 0.003;
  std::vector<PairCandidate> one, many;
  search.setThreads(1);
  search.find(topology, start, end, 1.25 * t, 0.8 * t, one);
  const long triangle_pairs = search.trianglePairs(), vertex_pairs = search.vertexPairs();
  ASSERT_GT(one.size(), 1000u);
  for (const int threads : {2, 3}) {
    search.setThreads(threads);
    search.find(topology, start, end, 1.25 * t, 0.8 * t, many);
    ASSERT_EQ(many.size(), one.size()) << threads << " threads";
    std::size_t same = 0;
    for (std::size_t k = 0; k < one.size(); ++k) {
      same += many[k].kind == one[k].kind && many[k].v == one[k].v;
    }
    EXPECT_EQ(same, one.size()) << threads << " threads";
    EXPECT_EQ(search.trianglePairs(), triangle_pairs) << threads << " threads";
    EXPECT_EQ(search.vertexPairs(), vertex_pairs) << threads << " threads";
  }
  std::printf("%zu pairs listed on 1, 2 and 3 threads\n", one.size());
}

TEST(ImpactFailsafe, StopsCrossingsAndReportsWhatPinsDrive) {
  const TwoSheets s(4, 0.1, 0.005, 0.011);
  SurfaceTopology topology(s.triangles, static_cast<int>(s.rest.cols()));
  PairSearch search(topology, s.rest);
  StepData data(s.rest);
  Points end = s.rest;
  for (int i = s.n2; i < 2 * s.n2; ++i) end(2, i) -= 0.02;  // straight through
  std::vector<PairCandidate> pairs;
  search.find(topology, s.rest, end, 0.001, 0.001, pairs);
  std::vector<PairContact> contacts(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    contacts[k].pair = pairs[k];
    PairPoints x;
    for (int j = 0; j < 4; ++j) x[j] = s.rest.col(pairs[k].v[j]);
    contacts[k].start_distance = closestPoints(pairs[k].kind, x).distance;
  }
  const std::vector<char> skip(contacts.size(), 0);
  IntersectionCounter counter(s.triangles);
  Points free_end = end;
  ImpactReport r = stopImpacts(contacts, skip, data.step(0.002), 0.002, 4, free_end, nullptr);
  EXPECT_GT(r.hits, 0);
  EXPECT_EQ(r.unresolved, 0);
  EXPECT_EQ(counter.count(free_end), 0);
  // The upper sheet hard-pinned and driven through: nothing movable can stop it.
  for (int i = s.n2; i < 2 * s.n2; ++i) data.movable[i] = 0;
  Points pinned_end = end;
  r = stopImpacts(contacts, skip, data.step(0.002), 0.002, 4, pinned_end, nullptr);
  EXPECT_GT(r.unresolved, 0);
}

TEST(TriangleSelfContact, SheetsThatCrossAreUntangled) {
  // The upper sheet tilted through the lower one: the two cross along a line. With no other
  // motion, the contour minimization pulls them apart within some substeps.
  const double t = 0.002;
  TwoSheets s(8, 0.1, 0.0, 0.02);
  for (int i = s.n2; i < 2 * s.n2; ++i) s.rest(2, i) = 0.3 * (s.rest(0, i) - 0.02);
  IntersectionCounter counter(s.triangles);
  const int tangled = counter.count(s.rest);
  ASSERT_GT(tangled, 0);
  TriangleSelfContact contact(s.triangles, s.rest, t, 0.3);
  Points x = s.rest, v = Points::Zero(3, s.rest.cols());
  int substeps = 0;
  while (counter.count(x) > 0 && substeps < 400) {
    StepData data(x);
    Points end = x;
    contact.resolve(data.step(0.002), GroundPlane{}, end, v);
    x = end;
    ++substeps;
  }
  std::printf("%d intersecting pairs untangled in %d substeps\n", tangled, substeps);
  EXPECT_EQ(counter.count(x), 0);
  EXPECT_LT(substeps, 400);
  // Once free, it stays free and keeps its distance.
  for (int k = 0; k < 20; ++k) {
    StepData data(x);
    Points end = x;
    contact.resolve(data.step(0.002), GroundPlane{}, end, v);
    x = end;
    EXPECT_EQ(counter.count(x), 0);
  }
  EXPECT_EQ(contact.lastStats().tangled_pairs, 0);
}

}  // namespace
}  // namespace cloth_sim
