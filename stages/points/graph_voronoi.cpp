// graph_voronoi: graph-Voronoi reconstruction of an unoriented point cloud
// (Dumitriu et al.; framework/points/graph_voronoi.h). Normals, if present,
// are ignored. Writes the mesh (vertices = the k-hop subsample) and the
// paper's Table 1/2 figures as gv_* metrics.
#include "framework/points/graph_voronoi.h"
#include "framework/points/graph_voronoi_full.h"
#include "framework/spatial/topology.h"
#include "registry/bind.h"
#include "stages/builtin.h"

namespace arcs {

namespace {

Binder<GraphVoronoiOptions> GraphVoronoiParams() {
  using O = GraphVoronoiOptions;
  return Binder<O>()
      .Int("kappa", &O::kappa, "nearest neighbours per point in the neighbourhood graph (paper: 15)", Closed(1, 256))
      .Int("k", &O::k, "hop distance of the independent set: sites are >= k hops apart (paper: 5)", Closed(1, 1000))
      .Bool("adapt_k", &O::adapt_k,
            "a cloud too small for k (its faces use < 4 sites: none or one triangle) is rerun with k-1, "
            "..., 2; the k used is the gv_k_used metric (off: the requested k only, else an error)")
      .Int("a", &O::a, "adjacency threshold: cells adjacent when b12 + b21 > a (paper: 7)", Closed(0, 1000000))
      .Int("max_face_size", &O::max_face_size, "longest cycle enumerated as a face", Closed(3, 64))
      .Int("cycle_search_budget", &O::cycle_search_budget,
           "DFS steps per start edge and cycle length before a search is abandoned (counted)",
           Closed(1, 1000000000))
      .Bool("merge_duplicates", &O::merge_duplicates, "merge bit-identical points into one graph node")
      .Double("outlier_ratio", &O::outlier_ratio,
              "0 = keep all points (paper); else (>= 1) drop points whose mean kNN distance exceeds "
              "this times the median",
              Closed(0.0, 1e12))
      .Bool("triangulate", &O::triangulate, "triangulate faces of more than three vertices (else left open)")
      .Bool("orient", &O::orient, "orient faces consistently, each component outward by signed volume")
      .Enum("vertex_position", &O::vertex_position, O::kVertexPositionNames,
            "vertex at the site's input point (paper) or at the mean of its Voronoi cell")
      .Unbound([] {
        ParamSchema tmp;
        tmp.Bool("full_resolution", false,
                 "bring every non-site point into the surface (each coarse face re-triangulated with the points "
                 "of its cells; same topology, vertices at the input points; beyond the paper)");
        return tmp.specs().front();
      }());
}

void RunGraphVoronoi(Context& ctx, CaseData& d, const GraphVoronoiOptions& o, const ParamMap& p) {
  GraphVoronoiResult res = ReconstructGraphVoronoi(d.points->P, o);
  const GraphVoronoiStats& st = res.stats;
  if (st.k_used != o.k)
    ctx.Warn("graph_voronoi: k = " + std::to_string(o.k) + " spans no surface on these " +
             std::to_string(st.input_points) + " points (too few sites); used k = " +
             std::to_string(st.k_used) + " (" + std::to_string(st.sites) + " sites; adapt_k)");
  if (p.GetBool("full_resolution")) {
    FullResolutionStats fs;
    res.mesh = RefineGraphVoronoi(d.points->P, res, {}, &fs);
    d.SetMetric("gv_full_vertices", static_cast<double>(fs.vertices));
    d.SetMetric("gv_full_pct_points", fs.pct_points);
    d.SetMetric("gv_full_s", fs.seconds);
    d.SetMetric("gv_full_folded", static_cast<double>(fs.folded_triangles));
    d.SetMetric("gv_full_merged", static_cast<double>(fs.merged_points));
    d.SetMetric("gv_full_dropped", static_cast<double>(fs.dropped_points));
    d.SetMetric("gv_full_flips", static_cast<double>(fs.flips));
  }
  const Topology topo = ComputeTopology(res.mesh);
  d.SetMetric("gv_prep_s", st.prep_s);
  d.SetMetric("gv_kdtree_s", st.kdtree_s);
  d.SetMetric("gv_knn_s", st.knn_s);
  d.SetMetric("gv_mis_s", st.mis_s);
  d.SetMetric("gv_voronoi_s", st.voronoi_s);
  d.SetMetric("gv_cdm_s", st.cdm_s);
  d.SetMetric("gv_cycles_s", st.cycles_s);
  d.SetMetric("gv_orient_s", st.orient_s);
  d.SetMetric("gv_triangulate_s", st.triangulate_s);
  d.SetMetric("gv_total_s", st.total_s);
  d.SetMetric("gv_samples", st.sites);
  d.SetMetric("gv_k_used", st.k_used);
  d.SetMetric("gv_cdm_edges", static_cast<double>(st.cdm_edges));
  d.SetMetric("gv_faces", static_cast<double>(st.faces));
  d.SetMetric("gv_pct_triangles", st.pct_triangles);
  d.SetMetric("gv_genus", st.genus_value);
  d.SetMetric("gv_unused_edges", static_cast<double>(st.unused_edges));
  d.SetMetric("gv_boundary_edges", static_cast<double>(st.boundary_edges));
  d.SetMetric("gv_closed", topo.closed ? 1 : 0);
  d.SetMetric("gv_manifold", topo.manifold ? 1 : 0);
  d.SetMetric("gv_mesh_genus", topo.genus);
  d.SetMetric("gv_duplicates", static_cast<double>(st.duplicates));
  d.SetMetric("gv_outliers_removed", static_cast<double>(st.outliers_removed));
  d.SetMetric("gv_truncated_searches", static_cast<double>(st.truncated_searches));
  if (!topo.closed || !topo.manifold)
    ctx.Warn("graph_voronoi: output is " + std::string(topo.closed ? "closed" : "open") + " and " +
             (topo.manifold ? "manifold" : "non-manifold") + " (" + std::to_string(st.boundary_edges) +
             " edges in one face, " + std::to_string(st.unused_edges) + " CDM edges in no face)");
  if (st.truncated_searches > 0)
    ctx.Warn("graph_voronoi: " + std::to_string(st.truncated_searches) +
             " cycle searches hit cycle_search_budget");
  d.output = std::move(res.mesh);
}

}  // namespace

void RegisterGraphVoronoi(Registry& r) {
  StageInfo s = DeclareStage("graph_voronoi", Role::kReconstructor,
                             "graph-Voronoi reconstruction of unoriented points (kNN graph, k-hop subsample, "
                             "combinatorial Delaunay map, cycle faces; Dumitriu et al.)",
                             {Slot::kPoints}, {Slot::kOutput}, k3D);
  s.outputs = {"gv_prep_s",      "gv_kdtree_s",     "gv_knn_s",        "gv_mis_s",        "gv_voronoi_s",
               "gv_cdm_s",       "gv_cycles_s",     "gv_orient_s",     "gv_triangulate_s",
               "gv_total_s",     "gv_samples",      "gv_cdm_edges",    "gv_faces",
               "gv_pct_triangles", "gv_genus",      "gv_unused_edges", "gv_boundary_edges",
               "gv_closed",      "gv_manifold",     "gv_mesh_genus",   "gv_duplicates",
               "gv_outliers_removed", "gv_truncated_searches",
               "gv_full_vertices", "gv_full_pct_points", "gv_full_s", "gv_full_folded", "gv_full_merged",
               "gv_full_dropped", "gv_full_flips", "gv_k_used"};
  BindStage<GraphVoronoiOptions>(s, GraphVoronoiParams(), RunGraphVoronoi);
  // full_resolution is the stage's, not GraphVoronoiOptions': its one
  // condition is checked beside the algorithm's Check(), at load.
  s.check = [bound = std::move(s.check)](const ParamMap& p) {
    bound(p);
    if (p.GetBool("full_resolution") && !p.GetBool("triangulate"))
      throw OptionError("full_resolution: needs triangulate: true");
  };
  r.Register(std::move(s));
}

}  // namespace arcs
