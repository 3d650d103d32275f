#include "framework/rfta/reach_for_the_arcs.h"

#include "framework/error.h"
#include "framework/rfta/sphere_set.h"
#include "framework/spatial/polyline_query.h"

namespace arcs {

namespace {

class PolylineTuningSurface final : public TuningSurface {
 public:
  explicit PolylineTuningSurface(Polyline c) : curve_(std::move(c)) {}
  void Prepare() override { bvh_ = std::make_unique<SegmentBvh>(curve_); }
  void ClosestPoints(const MatrixX3d& Q, VectorXd* sq_dist, MatrixX3d* points) const override {
    bvh_->ClosestPoints(Q, sq_dist, points);
  }
  double Closest(const Vec3& q, Vec3* point) const override {
    const SegmentBvh::Hit h = bvh_->Closest(q);
    *point = h.point;
    return h.sq_dist;
  }
  VectorXd WindingNumbers(const MatrixX3d& Q) const override { return WindingNumbers2D(curve_, Q); }

 private:
  Polyline curve_;
  std::unique_ptr<SegmentBvh> bvh_;
};

}  // namespace

std::unique_ptr<TuningSurface> MakePolylineTuningSurface(Polyline unit_frame_curve) {
  return std::make_unique<PolylineTuningSurface>(std::move(unit_frame_curve));
}

FineTuneResult FineTune2D(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                          const PointsToCurve& reconstruct, const FineTuneOptions& options, const Context& ctx) {
  if (samples.dim != 2) throw Error("fine_tune (2D): the samples are " + std::to_string(samples.dim) + "D");
  const PointsToSurface surface = [&](const PointCloud& pc,
                                      const UnitFrame& frame) -> std::unique_ptr<TuningSurface> {
    Polyline c = reconstruct(pc);
    if (c.Empty()) return nullptr;
    for (int v = 0; v < c.NumVertices(); ++v) c.V.row(v) = frame.ToUnit(c.V.row(v).transpose()).transpose();
    c.V.col(2).setZero();  // exactly in the plane (ToUnit subtracts z = 0 translation)
    return MakePolylineTuningSurface(std::move(c));
  };
  return FineTune(samples, initial, initial_sample, surface, options, ctx);
}

Rfta2DResult ReachForTheArcs2D(const SdfSamples& samples, const Rfta2DOptions& options, const Context& ctx) {
  if (samples.dim != 2) throw Error("rfta 2D: the samples are " + std::to_string(samples.dim) + "D, expected 2D");
  CheckRftaSamples(samples, "rfta");
  RequireBothSigns(SplitSpheresBySign(samples, SignSplitOptions{}), "rfta");
  const FreeSpaceSamples free = RasterizeFreeSpace(samples, options.raster, ctx, nullptr);
  ArcProjection a0 = ProjectToArcs(samples, free, options.projector, ctx);
  const PointsToCurve tuning = [&](const PointCloud& pc) { return ReconstructPoisson2D(pc, options.tuning_poisson, ctx); };
  Rfta2DResult r;
  r.tuning = FineTune2D(samples, a0.points, a0.sample, tuning, options.fine_tune, ctx);
  r.points = std::move(r.tuning.points);
  r.sample = std::move(r.tuning.sample);
  r.tuning.points = PointCloud();
  r.tuning.sample.clear();
  r.curve = ReconstructPoisson2D(r.points, options.poisson, ctx);
  if (r.curve.Empty()) throw Error("rfta 2D: the final reconstruction is empty");
  return r;
}

}  // namespace arcs
