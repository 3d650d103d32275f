// Reach for the Arcs in the plane (paper Fig. 5): the 3D pipeline of
// framework/rfta (sign separation, rasterisation with z = 0, the arc
// projector's circle-circle intersections, Alg. 3 fine-tuning) with a
// polyline as the reconstructed surface and the 2D screened Poisson
// reconstructor (poisson2d.h).
#pragma once

#include "framework/context.h"
#include "framework/reconstruct/poisson2d.h"
#include "framework/rfta/arc_projector.h"
#include "framework/rfta/fine_tune.h"
#include "framework/rfta/free_space.h"
#include "framework/types.h"

#include <functional>
#include <memory>

namespace arcs {

// A polyline already in the unit frame as the fine-tuner's surface: closest
// points by SegmentBvh, inside by the 2D winding number.
std::unique_ptr<TuningSurface> MakePolylineTuningSurface(Polyline unit_frame_curve);

// Reconstructs closed polylines (input frame) from oriented 2D points.
using PointsToCurve = std::function<Polyline(const PointCloud&)>;

// Algorithm 3 against a curve reconstructor (samples.dim must be 2). An
// empty curve stops the iterations early, as an empty mesh does in 3D.
FineTuneResult FineTune2D(const SdfSamples& samples, const PointCloud& initial, const std::vector<int>& initial_sample,
                          const PointsToCurve& reconstruct, const FineTuneOptions& options, const Context& ctx);

struct Rfta2DOptions {
  RasterizeOptions raster;
  ArcProjectorOptions projector;
  FineTuneOptions fine_tune;
  Poisson2DOptions poisson;         // the final reconstruction
  // The reconstructions inside fine-tuning: half as fine (as the `rfta`
  // stage's tuning reconstructor in 2D; they only steer the points).
  Poisson2DOptions tuning_poisson = [] {
    Poisson2DOptions o;
    o.resolution_shift = -1;
    return o;
  }();
};

struct Rfta2DResult {
  Polyline curve;           // closed polylines, counter-clockwise around the inside
  PointCloud points;        // the final tangency points (input frame, outward normals)
  std::vector<int> sample;  // SDF sample of each point
  FineTuneResult tuning;    // per-iteration statistics (its points are moved into `points`)
};

// The whole of Algorithm 1 on 2D samples, with the same streams and
// defaults as the stage pipeline [rasterize, arc_projector, fine_tune,
// screened_poisson_2d] (the `rfta` stage on dim-2 samples). Throws Error on
// samples that are not 2D, all of one sign, non-finite, or fewer than 2.
Rfta2DResult ReachForTheArcs2D(const SdfSamples& samples, const Rfta2DOptions& options, const Context& ctx);

}  // namespace arcs
