// Point-cloud input stages: sample_surface (point_sampler: reference mesh ->
// points with normals, with optional noise / outliers / duplicates),
// estimate_normals and subsample_points (point_modifier: points -> points).
#include "framework/points/normals.h"
#include "framework/points/sample_points.h"
#include "registry/bind.h"
#include "stages/builtin.h"

#include <algorithm>
#include <numeric>

namespace arcs {

namespace {

Binder<SurfacePointOptions> SampleSurfaceParams() {
  using O = SurfacePointOptions;
  return Binder<O>()
      .Int("count", &O::count, "number of surface samples", Closed(1, 100000000))
      .Double("noise_sigma", &O::noise_sigma, "std of isotropic Gaussian position noise, in mesh units (normals kept)",
              Closed(0.0, 1.0))
      .Double("outlier_fraction", &O::outlier_fraction,
              "outliers added (fraction of count): uniform in the 10 %-padded bounding box, random normals",
              Closed(0.0, 1.0))
      .Double("duplicate_fraction", &O::duplicate_fraction,
              "exact duplicates of random samples added (fraction of count)", Closed(0.0, 1.0));
}

void RunSampleSurface(Context& ctx, CaseData& d, const SurfacePointOptions& o, const ParamMap&) {
  d.points = SampleSurfacePoints(*d.reference, o, ctx.StreamSeed("sample_surface"));
  d.point_sample.clear();
}

// NormalOptions::method and ::orientation are strings (the algorithm's
// Check() refuses other names): they are choices of the schema, decoded
// into the struct by the stage.
Binder<NormalOptions> EstimateNormalsParams() {
  using O = NormalOptions;
  const O def;
  return Binder<O>()
      .Int("k", &O::k, "neighbours of the fit and of the orientation graph", Closed(3, 1000))
      .Choice("method", def.method, {"jet", "pca"}, "local fit: quadric jet (CGAL jet_estimate_normals) or plane (PCA)")
      .Choice("orientation", def.orientation, {"mst", "centroid", "none"},
              "mst: Hoppe et al. spanning tree from the top point (+z); centroid: away from the centroid; none: as fitted")
      .Choice("when", "missing", {"missing", "always"},
              "missing: keep normals the cloud already has; always: replace them");
}

void RunEstimateNormals(Context& ctx, CaseData& d, const NormalOptions& bound, const ParamMap& p) {
  if (d.points->Size() == 0) throw Error("the point cloud is empty");
  if (p.GetString("when") == "missing" && d.points->HasNormals()) {
    d.SetMetric("normals_estimated", 0);
    return;
  }
  NormalOptions o = bound;
  o.method = p.GetString("method");
  o.orientation = p.GetString("orientation");
  NormalReport rep;
  d.points->N = EstimateNormals(d.points->P, o, &rep);
  d.SetMetric("normals_estimated", 1);
  d.SetMetric("normals_unoriented", rep.unoriented);
  if (rep.unoriented > 0)
    ctx.Warn("estimate_normals: " + std::to_string(rep.unoriented) +
             " points outside the orientation graph's main component were oriented away from the centroid");
}

// No Options struct (a stage-level selection): the schema as is.
void RunSubsamplePoints(Context& ctx, CaseData& d, const ParamMap& p) {
  const int n = d.points->Size();
  std::int64_t keep = p.GetInt("count");
  if (keep == 0) keep = static_cast<std::int64_t>(std::llround(p.GetDouble("fraction") * n));
  if (keep >= n) return;
  // Partial Fisher-Yates on indices, then sorted so the kept rows keep their order.
  std::vector<int> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  Rng rng = ctx.MakeRng("subsample_points");
  for (std::int64_t i = 0; i < keep; ++i) {
    const auto j = i + static_cast<std::int64_t>(rng.UniformInt(static_cast<std::uint64_t>(n - i)));
    std::swap(idx[i], idx[j]);
  }
  std::sort(idx.begin(), idx.begin() + keep);
  PointCloud out;
  out.P.resize(keep, 3);
  const bool normals = d.points->HasNormals();
  if (normals) out.N.resize(keep, 3);
  for (std::int64_t i = 0; i < keep; ++i) {
    out.P.row(i) = d.points->P.row(idx[i]);
    if (normals) out.N.row(i) = d.points->N.row(idx[i]);
  }
  d.points = std::move(out);
  d.point_sample.clear();
}

}  // namespace

void RegisterPointInputStages(Registry& r) {
  {
    StageInfo s = DeclareStage(
        "sample_surface", Role::kPointSampler,
        "area-uniform points with face normals on the reference mesh (seeded), optional noise, outliers, duplicates",
        {Slot::kReference}, {Slot::kPoints}, k3D);
    BindStage<SurfacePointOptions>(s, SampleSurfaceParams(), RunSampleSurface);
    r.Register(std::move(s));
  }
  {
    StageInfo s = DeclareStage(
        "estimate_normals", Role::kPointModifier,
        "normals by CGAL jet (or PCA) fitting to k neighbours, consistently oriented by a minimum spanning tree",
        {Slot::kPoints}, {Slot::kPoints}, k3D);
    s.outputs = {"normals_estimated", "normals_unoriented"};
    BindStage<NormalOptions>(s, EstimateNormalsParams(), RunEstimateNormals);
    r.Register(std::move(s));
  }
  {
    StageInfo s = DeclareStage(
        "subsample_points", Role::kPointModifier,
        "a seeded uniformly random subset of the points (without replacement), e.g. to thin a dense scan",
        {Slot::kPoints}, {Slot::kPoints}, k3D);
    s.params.Int("count", 0, "points to keep (0 = use fraction); more than the cloud has keeps all", 0, 1000000000)
        .Double("fraction", 1.0, "fraction of the points to keep when count is 0", 0.0, 1.0);
    s.factory = FunctionStage(RunSubsamplePoints);
    r.Register(std::move(s));
  }
}

}  // namespace arcs
