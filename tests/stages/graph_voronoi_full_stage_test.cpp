// graph_voronoi's full_resolution option through the registry, as an
// experiment runs it: sample_surface -> graph_voronoi {full_resolution: true}.
#include "framework/error.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/spatial/topology.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace arcs {
namespace {

// The metric's value, NaN when the stage did not set it.
double Metric(const CaseData& d, const std::string& name) {
  for (const auto& [k, v] : d.metrics)
    if (k == name) return v;
  return std::numeric_limits<double>::quiet_NaN();
}

void RunStage(const Registry& r, const std::string& name, const ParamMap& given, Context& ctx, CaseData& d) {
  r.Get(name).factory(r.Resolve(name, given))->Run(ctx, d);
}

TEST(GraphVoronoiFullStage, EveryPointIsAVertexAndTheCoarseTopologyStays) {
  Registry r;
  RegisterBuiltinStages(r);
  Context ctx(3);
  CaseData base;
  base.registry = &r;
  base.reference = MakeIcosphere(0.5, 5);
  ParamMap n;
  n.Set("count", std::int64_t{12000});
  RunStage(r, "sample_surface", n, ctx, base);

  CaseData coarse = base, full = base;
  RunStage(r, "graph_voronoi", {}, ctx, coarse);
  ParamMap fr;
  fr.Set("full_resolution", true);
  RunStage(r, "graph_voronoi", fr, ctx, full);
  const Topology tc = ComputeTopology(*coarse.output), tf = ComputeTopology(*full.output);
  EXPECT_LT(tc.vertices, 600);
  EXPECT_GE(tf.referenced_vertices, 12000 * 99 / 100);
  // The coarse topology, at full resolution (this sample's coarse mesh is closed,
  // with one non-manifold vertex, which stays).
  EXPECT_TRUE(tc.closed);
  EXPECT_EQ(tf.closed, tc.closed);
  EXPECT_EQ(tf.boundary_edges, tc.boundary_edges);
  EXPECT_EQ(tf.nonmanifold_edges, tc.nonmanifold_edges);
  EXPECT_EQ(tf.nonmanifold_vertices, tc.nonmanifold_vertices);
  EXPECT_EQ(tf.genus, tc.genus);
  EXPECT_EQ(tf.components, tc.components);
  EXPECT_GE(Metric(full, "gv_full_pct_points"), 99.0);
  EXPECT_EQ(Metric(full, "gv_full_vertices"), tf.referenced_vertices);
  EXPECT_EQ(Metric(full, "gv_closed"), 1);
  EXPECT_TRUE(std::isnan(Metric(coarse, "gv_full_vertices")));

  ParamMap bad;
  bad.Set("full_resolution", true);
  bad.Set("triangulate", false);
  CaseData d = base;
  try {
    RunStage(r, "graph_voronoi", bad, ctx, d);
    FAIL() << "full_resolution without triangulate must fail";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("triangulate"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace arcs
