#include "framework/rfta/sphere_carve.h"

#include "framework/error.h"
#include "framework/rfta/sphere_set.h"
#include "framework/rfta/sphere_tree.h"
#include "framework/util/parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace arcs {

double CarveMargin(const SdfSamples& samples, double tol_unit, double fraction) {
  const double tol = tol_unit * ComputeUnitFrame(samples).scale;
  return fraction > 0 ? std::max(tol, fraction * SampleSpacing(samples)) : tol;
}

CarveField OutsideSpheresCarve(const SdfSamples& samples, double margin) {
  if (samples.dim != 3)
    throw Error("carve outside_spheres: needs 3D SDF samples, got " + std::to_string(samples.dim) + "D");
  if (!(margin >= 0)) throw Error("carve outside_spheres: margin must be >= 0");
  std::int64_t count = 0;
  for (std::int64_t i = 0; i < samples.Size(); ++i) count += samples.values[i] > 0;
  if (count == 0) throw Error("carve outside_spheres: no sample is positive (no ball certifies empty space)");
  MatrixX3d centers(count, 3);
  VectorXd radii(count);
  std::vector<int> ids(static_cast<std::size_t>(count));
  std::int64_t k = 0;
  for (std::int64_t i = 0; i < samples.Size(); ++i) {
    if (!(samples.values[i] > 0)) continue;
    centers.row(k) = samples.points.row(i).head<3>();
    radii[k] = samples.values[i];
    ids[static_cast<std::size_t>(k)] = static_cast<int>(i);
    ++k;
  }
  auto tree = std::make_shared<const SphereTree>(centers, radii, ids);
  CarveField f;
  // c(x) = -min over the balls of (|x - p| - s) - margin. `near` works per
  // block (a cube of half the samples' spacing), with what it learns of a
  // block kept for later batches (per reach): a block that one ball covers
  // with reach + margin to spare is claimed whole (c >= reach); otherwise it
  // keeps the balls that can come within reach - margin of it
  // (SphereTree::LocalSet), deepest first at the block's centre. A point
  // takes the minimum over that list, which is the minimum over all balls
  // wherever it is below reach - margin: the same terms as DistanceToUnion's,
  // so the same bits; the scan stops at a ball it lies reach + margin inside.
  // Session 42: a tree query per crossed edge, serially in the marching
  // cubes, was most of carving's cost; then a list per batch's block (the
  // marching cubes' rounds are thin shells), then the blocks far inside the
  // balls, each with thousands in its list.
  struct Block {
    bool deep = false;
    std::vector<int> balls;  // deepest first at the block's centre
  };
  struct Blocks {
    std::mutex mutex;
    double reach = -1;
    std::unordered_map<std::uint64_t, Block> known;
  };
  auto blocks = std::make_shared<Blocks>();
  const double block = 0.5 * SampleSpacing(samples);
  if (!(block > 0)) throw Error("carve outside_spheres: the samples' spacing is not positive");
  f.near = [tree, margin, block, blocks](const std::vector<Vec3>& x, double reach, std::vector<double>& c) {
    c.assign(x.size(), -std::numeric_limits<double>::infinity());
    if (x.empty()) return;
    if (!(reach > 0)) throw Error("carve outside_spheres: reach must be > 0");
    std::lock_guard<std::mutex> lock(blocks->mutex);
    if (reach != blocks->reach) {
      blocks->known.clear();
      blocks->reach = reach;
    }
    const double cut = reach - margin;  // c > -reach iff the distance < cut
    const double deep = -(reach + margin);  // c >= reach iff the distance <= deep
    // Collected with room for rounding in the list's own tests.
    const double collect = cut + 1e-9 * (std::abs(cut) + block);
    auto cell = [&](double v) { return static_cast<std::int64_t>(std::floor(v / block)); };
    const std::int64_t kOff = std::int64_t{1} << 20;
    auto key_of = [&](const Vec3& p) {
      std::uint64_t key = 0;
      for (int a = 0; a < 3; ++a) key = (key << 21) | (static_cast<std::uint64_t>(cell(p[a]) + kOff) & 0x1FFFFF);
      return key;
    };
    // (block key, index), sorted: each group is a run of one key.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(x.size());
    std::atomic<bool> off_grid{false};
    ParallelFor(static_cast<std::int64_t>(x.size()), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t i = b; i < e; ++i) {
        for (int a = 0; a < 3; ++a)
          if (!(std::abs(x[i][a] / block) < static_cast<double>(kOff - 1))) off_grid = true;
        order[i] = {key_of(x[i]), static_cast<std::uint32_t>(i)};
      }
    }, 4096);
    if (off_grid)
      throw Error("carve outside_spheres: a point lies more than 2^20 blocks (half the samples' spacing) from the "
                  "origin, or is not finite");
    std::sort(order.begin(), order.end());
    std::vector<std::size_t> starts;
    std::vector<std::size_t> missing;  // groups whose block is not known yet
    for (std::size_t i = 0; i < order.size(); ++i)
      if (i == 0 || order[i].first != order[i - 1].first) {
        if (!blocks->known.count(order[i].first)) missing.push_back(starts.size());
        starts.push_back(i);
      }
    starts.push_back(order.size());
    std::vector<Block> made(missing.size());
    ParallelFor(static_cast<std::int64_t>(missing.size()), [&](std::int64_t b, std::int64_t e) {
      SphereTree::LocalSet local;
      for (std::int64_t m = b; m < e; ++m) {
        const Vec3& p = x[order[starts[missing[m]]].second];
        Vec3 lo, hi;
        for (int a = 0; a < 3; ++a) {
          const double c0 = static_cast<double>(cell(p[a]));
          // The block, widened by a relative 1e-9 of its edge for rounding.
          lo[a] = c0 * block - 1e-9 * block;
          hi[a] = (c0 + 1) * block + 1e-9 * block;
        }
        // A ball holding the block grown by reach + margin holds every
        // point's ball of that radius: all of them are reach + margin deep.
        const Vec3 grow = Vec3::Constant(reach + margin);
        if (tree->AnyCoversBox(lo - grow, hi + grow, 1.0)) {
          made[m].deep = true;
          continue;
        }
        tree->CollectLocal(lo, hi, collect, &local);
        const Vec3 mid = 0.5 * (lo + hi);
        std::vector<std::pair<double, int>> by_depth(local.balls.size());
        for (std::size_t j = 0; j < local.balls.size(); ++j) {
          const SphereTree::Ball& ball = tree->ball(local.balls[j]);
          by_depth[j] = {(mid - Vec3(ball.x, ball.y, ball.z)).norm() - ball.r, local.balls[j]};
        }
        std::sort(by_depth.begin(), by_depth.end());
        made[m].balls.resize(by_depth.size());
        for (std::size_t j = 0; j < by_depth.size(); ++j) made[m].balls[j] = by_depth[j].second;
      }
    }, 4);
    for (std::size_t m = 0; m < missing.size(); ++m)
      blocks->known.emplace(order[starts[missing[m]]].first, std::move(made[m]));
    std::vector<const Block*> group_block(starts.size() - 1);
    for (std::size_t g = 0; g + 1 < starts.size(); ++g) group_block[g] = &blocks->known.at(order[starts[g]].first);
    ParallelFor(static_cast<std::int64_t>(starts.size() - 1), [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t g = b; g < e; ++g) {
        const Block& blk = *group_block[g];
        for (std::size_t j = starts[g]; j < starts[g + 1]; ++j) {
          const std::uint32_t i = order[j].second;
          if (blk.deep) {
            c[i] = std::numeric_limits<double>::infinity();
            continue;
          }
          const double best = tree->MinDistance(x[i], blk.balls, deep);
          if (best <= deep) c[i] = std::numeric_limits<double>::infinity();
          else if (best < cut) c[i] = -best - margin;
        }
      }
    }, 16);
  };
  f.value = [tree, margin](const Vec3& x) { return -tree->DistanceToUnion(x, 1.0) - margin; };
  return f;
}

}  // namespace arcs
