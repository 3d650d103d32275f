// The `arcs._arcs` extension module: the framework's stages on numpy arrays.
//
// This translation unit is the only one that sees pybind11 and Python. It
// exposes a small generic core; python/arcs/__init__.py builds the public
// functions (reach_for_the_arcs, reconstruct, ...) on it, with keyword
// parameters, defaults and docstrings taken from the stage schemas.
//
// Conventions:
//  * Arrays in: any numeric dtype / layout, converted once into the
//    framework's own (row-major, owning) Eigen matrices. That one copy is
//    needed because the framework's containers own their storage.
//  * Arrays out: no copy. The Eigen matrix is moved onto the heap and the
//    numpy array views it, owning it through a capsule.
//  * Every framework call runs with the GIL released (py::gil_scoped_release).
//  * arcs::Error (bad input, bad parameter, malformed file) becomes
//    ValueError with the same message the CLI prints after "arcs: error: ".
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "framework/error.h"
#include "orchestration/csv.h"
#include "orchestration/memory.h"
#include "orchestration/spec.h"
#include "orchestration/runner.h"
#include "orchestration/version.h"
#include "framework/geometry/builtin_shapes.h"
#include "framework/io/mesh_io.h"
#include "framework/io/points_io.h"
#include "framework/io/sdf_io.h"
#include "framework/sdf/sdf_sampling.h"
#include "framework/spatial/winding_number.h"
#include "framework/util/parallel.h"
#include "registry/plugin.h"
#include "registry/plugin_api.h"
#include "registry/registry.h"
#include "stages/builtin.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace arcs;

namespace {

Registry& TheRegistry() {
  static Registry* r = [] {
    auto* reg = new Registry;  // lives as long as the interpreter (stages hold no Python objects)
    RegisterBuiltinStages(*reg);
    return reg;
  }();
  return *r;
}

int g_threads = 0;  // 0 = all cores (set_threads)

// ---- arrays in ------------------------------------------------------------

using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

std::string ShapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// An (N, cols) float array (cols 0 = 2 or 3) with finite entries.
MatrixXd Rows(const py::handle& obj, const std::string& what, int cols) {
  DArray a = DArray::ensure(obj);
  if (!a) throw Error(what + ": expected a numeric array");
  if (a.ndim() != 2 || (cols > 0 && a.shape(1) != cols) || (cols == 0 && a.shape(1) != 2 && a.shape(1) != 3))
    throw Error(what + ": expected shape (N, " + (cols > 0 ? std::to_string(cols) : std::string("2 or 3")) +
                "), got " + ShapeText(a));
  MatrixXd m(a.shape(0), a.shape(1));
  const double* p = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(p[i]))
      throw Error(what + ": row " + std::to_string(i / a.shape(1)) + " has a non-finite value");
    m.data()[i] = p[i];
  }
  return m;
}

MatrixX3d Rows3(const py::handle& obj, const std::string& what) {
  const MatrixXd m = Rows(obj, what, 3);
  return MatrixX3d(m);
}

VectorXd Values(const py::handle& obj, const std::string& what) {
  DArray a = DArray::ensure(obj);
  if (!a) throw Error(what + ": expected a numeric array");
  if (!(a.ndim() == 1 || (a.ndim() == 2 && a.shape(1) == 1)))
    throw Error(what + ": expected shape (N,), got " + ShapeText(a));
  VectorXd v(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    if (!std::isfinite(a.data()[i])) throw Error(what + ": entry " + std::to_string(i) + " is not finite");
    v[i] = a.data()[i];
  }
  return v;
}

Mesh MeshFrom(const py::handle& V, const py::handle& F, const std::string& what) {
  Mesh m;
  m.V = Rows3(V, what + " V");
  IArray f = IArray::ensure(F);
  if (!f || f.ndim() != 2 || f.shape(1) != 3)
    throw Error(what + " F: expected an integer array of shape (#F, 3)" + (f ? ", got " + ShapeText(f) : std::string()));
  m.F.resize(f.shape(0), 3);
  for (py::ssize_t i = 0; i < f.size(); ++i) {
    const std::int64_t x = f.data()[i];
    if (x < 0 || x >= m.V.rows())
      throw Error(what + " F: face " + std::to_string(i / 3) + " has vertex index " + std::to_string(x) +
                  " outside [0, " + std::to_string(m.V.rows()) + ")");
    m.F.data()[i] = static_cast<int>(x);
  }
  return m;
}

// ---- arrays out (no copy) -------------------------------------------------

template <class M>
py::array Own(M&& m) {
  using Mat = std::decay_t<M>;
  using T = typename Mat::Scalar;
  auto* heap = new Mat(std::forward<M>(m));
  py::capsule owner(heap, [](void* p) { delete static_cast<Mat*>(p); });
  std::vector<py::ssize_t> shape, strides;
  if (Mat::ColsAtCompileTime == 1) {
    shape = {static_cast<py::ssize_t>(heap->rows())};
    strides = {static_cast<py::ssize_t>(sizeof(T))};
  } else {
    shape = {static_cast<py::ssize_t>(heap->rows()), static_cast<py::ssize_t>(heap->cols())};
    strides = {static_cast<py::ssize_t>(sizeof(T) * heap->cols()), static_cast<py::ssize_t>(sizeof(T))};
  }
  return py::array_t<T>(shape, strides, heap->data(), owner);
}

// Grid values (arcs order, x fastest) as a numpy (nx, ny[, nz]) array in C order.
py::array GridArray(const VectorXd& values, const GridInfo& g) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dim == 3 ? g.dims[2] : 1;
  std::vector<py::ssize_t> shape = {nx, ny};
  if (g.dim == 3) shape.push_back(nz);
  py::array_t<double> out(shape);
  double* o = out.mutable_data();
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        o[(static_cast<std::int64_t>(i) * ny + j) * nz + k] = values[i + static_cast<std::int64_t>(nx) * (j + static_cast<std::int64_t>(ny) * k)];
  return out;
}

py::tuple Bounds(const GridInfo& g) {
  py::list lo, hi;
  for (int a = 0; a < g.dim; ++a) {
    lo.append(g.min[a]);
    hi.append(g.max[a]);
  }
  return py::make_tuple(py::tuple(lo), py::tuple(hi));
}

// ---- parameters -----------------------------------------------------------

ParamValue ToParam(const std::string& stage, const ParamSpec& spec, const py::handle& v);

std::shared_ptr<StageSpec> ToStageSpec(const std::string& stage, const std::string& param, const py::handle& v) {
  auto s = std::make_shared<StageSpec>();
  if (py::isinstance<py::str>(v)) {
    s->stage = v.cast<std::string>();
    return s;
  }
  // (name, {params}) or {"stage": name, "params": {...}}
  py::object name, params;
  if (py::isinstance<py::tuple>(v) && py::len(v) == 2) {
    name = v[py::int_(0)];
    params = v[py::int_(1)];
  } else if (py::isinstance<py::dict>(v) && v.contains("stage")) {
    name = v["stage"];
    params = v.contains("params") ? py::object(v["params"]) : py::object(py::dict());
  } else {
    throw OptionError(stage + "." + param + ": a nested stage is a name, (name, {params}) or {'stage': name, 'params': {...}}");
  }
  s->stage = py::str(name).cast<std::string>();
  const StageInfo& info = TheRegistry().Get(s->stage);
  for (auto [k, x] : params.cast<py::dict>()) {
    const std::string key = py::str(k).cast<std::string>();
    const ParamSpec* ps = info.params.Find(key);
    if (!ps) {
      std::string valid;
      for (const auto& p : info.params.specs()) valid += (valid.empty() ? "" : ", ") + p.name;
      throw OptionError("stage '" + s->stage + "' has no parameter '" + key + "' (valid: " + valid + ")");
    }
    s->params.Set(key, ToParam(s->stage, *ps, x));
  }
  return s;
}

ParamValue ToParam(const std::string& stage, const ParamSpec& spec, const py::handle& v) {
  const std::string where = stage + "." + spec.name;
  const bool is_bool = py::isinstance<py::bool_>(v) || py::str(py::type::of(v).attr("__name__")).cast<std::string>() == "bool_";
  switch (spec.type) {
    case ParamType::kBool:
      if (!is_bool) throw OptionError(where + ": must be True or False, got " + py::repr(v).cast<std::string>());
      return v.cast<bool>();
    case ParamType::kInt:
      if (is_bool || !py::hasattr(v, "__index__"))
        throw OptionError(where + ": must be an integer, got " + py::repr(v).cast<std::string>());
      return py::int_(py::reinterpret_borrow<py::object>(v)).cast<std::int64_t>();
    case ParamType::kDouble:
      if (is_bool || !(py::hasattr(v, "__float__")))
        throw OptionError(where + ": must be a number, got " + py::repr(v).cast<std::string>());
      return py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
    case ParamType::kString:
    case ParamType::kChoice:
      if (!py::isinstance<py::str>(v)) throw OptionError(where + ": must be a string, got " + py::repr(v).cast<std::string>());
      return v.cast<std::string>();
    case ParamType::kStage: return ToStageSpec(stage, spec.name, v);
  }
  throw OptionError(where + ": unsupported parameter type");
}

ParamMap ToParams(const std::string& stage, const py::dict& kwargs) {
  const StageInfo& info = TheRegistry().Get(stage);
  ParamMap given;
  for (auto [k, v] : kwargs) {
    const std::string key = py::str(k).cast<std::string>();
    const ParamSpec* spec = info.params.Find(key);
    if (!spec) {
      std::string valid;
      for (const auto& p : info.params.specs()) valid += (valid.empty() ? "" : ", ") + p.name;
      throw OptionError("stage '" + stage + "' has no parameter '" + key + "'" +
                        (valid.empty() ? " (it takes none)" : " (valid: " + valid + ")"));
    }
    given.Set(key, ToParam(stage, *spec, v));
  }
  return TheRegistry().Resolve(stage, given);
}

py::object FromParam(const ParamValue& v) {
  if (auto* b = std::get_if<bool>(&v)) return py::bool_(*b);
  if (auto* i = std::get_if<std::int64_t>(&v)) return py::int_(*i);
  if (auto* d = std::get_if<double>(&v)) return py::float_(*d);
  if (auto* s = std::get_if<std::string>(&v)) return py::str(*s);
  const auto& st = *std::get<std::shared_ptr<StageSpec>>(v);
  if (st.params.items().empty()) return py::str(st.stage);
  py::dict p;
  for (const auto& [k, x] : st.params.items()) p[py::str(k)] = FromParam(x);
  return py::make_tuple(st.stage, p);
}

// ---- the generic core -----------------------------------------------------

// inputs (all optional):
//   reference: (V, F)                      the reference mesh
//   mesh: (V, F)                           an output mesh (for evaluators)
//   U, S: (N, d) points and (N,) values    scattered SDF samples
//   grid: (nx, ny[, nz]) values, bounds: ((min...), (max...))   grid SDF samples
//   P, N: (N, 3) points and normals        a point cloud
// Runs the stages in order (each (name, params dict)) on one case and
// returns what they produced.
py::dict RunPipeline(const py::list& pipeline, const py::dict& inputs, std::uint64_t seed) {
  CaseData d;
  d.registry = &TheRegistry();
  if (inputs.contains("reference")) {
    auto t = inputs["reference"].cast<py::tuple>();
    d.reference = MeshFrom(t[0], t[1], "reference");
  }
  if (inputs.contains("mesh")) {
    auto t = inputs["mesh"].cast<py::tuple>();
    d.output = MeshFrom(t[0], t[1], "mesh");
  }
  if (inputs.contains("U") || inputs.contains("S")) {
    if (!inputs.contains("U") || !inputs.contains("S")) throw Error("SDF samples need both U (points) and S (values)");
    SdfSamples s;
    s.points = Rows(inputs["U"], "U", 0);
    s.values = Values(inputs["S"], "S");
    s.dim = static_cast<int>(s.points.cols());
    if (s.points.rows() != s.values.size())
      throw Error("U has " + std::to_string(s.points.rows()) + " points but S has " + std::to_string(s.values.size()) +
                  " values (they must have the same length)");
    if (s.values.size() == 0) throw Error("U and S are empty (no SDF samples)");
    d.samples = std::move(s);
  }
  if (inputs.contains("grid")) {
    DArray a = DArray::ensure(inputs["grid"]);
    if (!a || (a.ndim() != 3 && a.ndim() != 2))
      throw Error("S: a grid must have shape (nx, ny, nz) or (nx, ny)" + (a ? ", got " + ShapeText(a) : std::string()));
    NpyArray arr;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) arr.shape.push_back(a.shape(i));
    arr.data.assign(a.data(), a.data() + a.size());
    std::array<double, 3> lo{-1, -1, -1}, hi{1, 1, 1};
    if (inputs.contains("bounds") && !inputs["bounds"].is_none()) {
      auto b = inputs["bounds"].cast<py::sequence>();
      if (py::len(b) != 2) throw Error("bounds: expected (min, max), each with one value per axis");
      auto bl = b[0].cast<std::vector<double>>(), bh = b[1].cast<std::vector<double>>();
      if (static_cast<int>(bl.size()) != a.ndim() || static_cast<int>(bh.size()) != a.ndim())
        throw Error("bounds: expected " + std::to_string(a.ndim()) + " values per corner for a grid of shape " + ShapeText(a));
      for (int i = 0; i < a.ndim(); ++i) {
        lo[i] = bl[i];
        hi[i] = bh[i];
      }
    }
    d.samples = SdfGridFromArray("S", arr, lo, hi);
  }
  if (inputs.contains("P")) {
    PointCloud pc;
    pc.P = Rows3(inputs["P"], "P");
    if (inputs.contains("N") && !inputs["N"].is_none()) {
      pc.N = Rows3(inputs["N"], "N");
      if (pc.N.rows() != pc.P.rows())
        throw Error("N has " + std::to_string(pc.N.rows()) + " normals but P has " + std::to_string(pc.P.rows()) +
                    " points (they must have the same length)");
    }
    if (pc.P.rows() == 0) throw Error("P is empty (no points)");
    d.points = std::move(pc);
  }
  std::vector<std::pair<std::string, ParamMap>> stages;
  for (auto item : pipeline) {
    auto t = item.cast<py::tuple>();
    const std::string name = t[0].cast<std::string>();
    stages.emplace_back(name, ToParams(name, t[1].cast<py::dict>()));
  }
  {
    py::gil_scoped_release release;
    ThreadLimit limit(g_threads);
    Context ctx(seed);
    ctx.set_log([](LogLevel l, const std::string& m) {
      if (l >= LogLevel::kWarning) std::fprintf(stderr, "%s\n", m.c_str());
    });
    for (const auto& [name, params] : stages) TheRegistry().Get(name).factory(params)->Run(ctx, d);
  }
  py::dict out;
  if (d.output) {
    out["V"] = Own(std::move(d.output->V));
    out["F"] = Own(std::move(d.output->F));
  }
  if (d.output_curve) {
    out["curve_V"] = Own(std::move(d.output_curve->V));
    out["curve_E"] = Own(std::move(d.output_curve->E));
  }
  if (d.points) {
    out["P"] = Own(std::move(d.points->P));
    if (d.points->N.rows() > 0) out["N"] = Own(std::move(d.points->N));
  }
  if (d.samples) {
    if (d.samples->grid) {
      out["grid"] = GridArray(d.samples->values, *d.samples->grid);
      out["bounds"] = Bounds(*d.samples->grid);
    }
    out["U"] = Own(std::move(d.samples->points));
    out["S"] = Own(std::move(d.samples->values));
  }
  if (d.volume) {
    out["volume"] = GridArray(d.volume->values, d.volume->info);
    out["volume_bounds"] = Bounds(d.volume->info);
  }
  py::dict metrics;
  for (const auto& [k, v] : d.metrics) metrics[py::str(k)] = v;
  out["metrics"] = metrics;
  return out;
}

py::list StageList() {
  py::list out;
  for (const StageInfo* s : TheRegistry().List()) {
    py::dict d;
    d["name"] = s->name;
    d["role"] = RoleName(s->role);
    d["doc"] = s->doc;
    d["origin"] = s->origin;
    py::list params;
    for (const auto& p : s->params.specs()) {
      py::dict q;
      q["name"] = p.name;
      q["type"] = ParamTypeName(p.type);
      q["default"] = FromParam(p.default_value);
      q["allowed"] = p.RangeText();
      q["doc"] = p.doc;
      if (p.type == ParamType::kChoice) q["choices"] = p.choices;
      if (p.type == ParamType::kStage) q["stage_role"] = p.stage_role;
      params.append(q);
    }
    d["params"] = params;
    d["outputs"] = s->outputs;
    out.append(d);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_arcs, m) {
  m.doc() = "arcs: surfaces from signed distances and point clouds (the C++ core; use the `arcs` package)";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const arcs::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.def("run_pipeline", &RunPipeline, py::arg("pipeline"), py::arg("inputs"), py::arg("seed") = 1,
        "Runs stages [(name, {params})] on one case built from `inputs`; returns a dict of what they produced.");
  m.def("stages", &StageList, "Every registered stage with its parameter schema.");
  m.def("set_threads", [](int t) {
    if (t < 0) throw Error("threads must be >= 0 (0 = all cores), got " + std::to_string(t));
    g_threads = t;
  }, py::arg("threads"), "Threads for later calls (0 = all cores).");
  m.def("get_threads", [] { return g_threads; });
  m.def("keep_freed_memory", [] { return KeepFreedMemory(); },
        "Asks glibc's malloc to keep freed memory for reuse (as the arcs command does): RFTA's solves then "
        "do not fault tens of MB in again each (about 15 % of its time). Process-wide, so not done on import; "
        "returns False where the allocator refused or is not glibc's.");
  m.def("signed_distance", [](const py::object& Q, const py::object& V, const py::object& F, bool exact) {
    const Mesh mesh = MeshFrom(V, F, "mesh");
    const MatrixX3d q = Rows3(Q, "Q");
    if (mesh.F.rows() == 0) throw Error("signed_distance: the mesh has no faces");
    VectorXd s;
    {
      py::gil_scoped_release release;
      ThreadLimit limit(g_threads);
      s = SignedDistance(mesh, q, exact ? SdfSign::kExactWindingNumber : SdfSign::kFastWindingNumber);
    }
    return Own(std::move(s));
  }, py::arg("Q"), py::arg("V"), py::arg("F"), py::arg("exact") = false);
  m.def("winding_number", [](const py::object& V, const py::object& F, const py::object& Q, bool exact) {
    const Mesh mesh = MeshFrom(V, F, "mesh");
    const MatrixX3d q = Rows3(Q, "Q");
    VectorXd w;
    {
      py::gil_scoped_release release;
      ThreadLimit limit(g_threads);
      w = exact ? WindingNumbersExact(mesh, q) : FastWindingNumber(mesh).Eval(q);
    }
    return Own(std::move(w));
  }, py::arg("V"), py::arg("F"), py::arg("Q"), py::arg("exact") = false);
  m.def("shape", [](const std::string& name) {
    Mesh mesh = MakeBuiltinShape(name);
    return py::make_tuple(Own(std::move(mesh.V)), Own(std::move(mesh.F)));
  }, py::arg("name"), "(V, F) of a built-in shape: sphere, torus, knot, two_tori.");
  m.def("read_mesh", [](const std::string& path) {
    Mesh mesh;
    {
      py::gil_scoped_release release;
      mesh = ReadMesh(path);
    }
    return py::make_tuple(Own(std::move(mesh.V)), Own(std::move(mesh.F)));
  }, py::arg("path"), "(V, F) of an OBJ/OFF/PLY/STL file.");
  m.def("write_mesh", [](const std::string& path, const py::object& V, const py::object& F) {
    const Mesh mesh = MeshFrom(V, F, "mesh");
    py::gil_scoped_release release;
    WriteMesh(path, mesh);
  }, py::arg("path"), py::arg("V"), py::arg("F"), "Writes an OBJ/OFF/PLY/STL file (by extension).");
  m.def("read_points", [](const std::string& path) {
    PointCloud pc;
    {
      py::gil_scoped_release release;
      pc = ReadPointCloud(path);
    }
    py::object n = pc.HasNormals() ? py::object(Own(std::move(pc.N))) : py::object(py::none());
    return py::make_tuple(Own(std::move(pc.P)), n);
  }, py::arg("path"), "(P, N or None) of a PLY/XYZ/PCD point cloud.");
  m.def("read_sdf", [](const std::string& path) {
    SdfSamples s;
    {
      py::gil_scoped_release release;
      s = ReadSdf(path);
    }
    py::dict out;
    if (s.grid) {
      out["grid"] = GridArray(s.values, *s.grid);
      out["bounds"] = Bounds(*s.grid);
    }
    out["U"] = Own(std::move(s.points));
    out["S"] = Own(std::move(s.values));
    return out;
  }, py::arg("path"));
  m.def("run_experiment", [](const std::string& path, const std::vector<std::string>& overrides, const std::string& out,
                             int jobs, int threads, bool isolate, bool save_outputs, bool progress) {
    if (jobs < 1) throw Error("jobs must be >= 1, got " + std::to_string(jobs));
    if (threads < 0) throw Error("threads must be >= 0, got " + std::to_string(threads));
    const Experiment exp = LoadExperiment(path, overrides, TheRegistry());
    RunOptions o;
    o.out_dir = out.empty() ? DefaultOutDir(exp) : out;
    o.jobs = jobs;
    o.threads = threads;
    o.isolate = isolate;
    o.save_outputs = save_outputs;
    o.progress = progress;
    o.command_line = {"python", "arcs.run", path};
    for (const auto& s : overrides) o.command_line.push_back("--set=" + s);
    RunSummary s;
    {
      py::gil_scoped_release release;
      s = RunExperiment(exp, TheRegistry(), o);
    }
    py::dict d;
    d["out_dir"] = o.out_dir;
    d["total"] = s.total;
    d["skipped"] = s.skipped;
    d["ok"] = s.ok;
    d["failed"] = s.failed;
    d["interrupted"] = s.interrupted;
    return d;
  }, py::arg("path"), py::arg("overrides"), py::arg("out"), py::arg("jobs"), py::arg("threads"), py::arg("isolate"),
        py::arg("save_outputs"), py::arg("progress"));
  m.def("version", [] {
    return std::string("arcs 0.1.0 (git ") + GitRevision() + ", " + BuildType() + " build, plugin API " +
           std::to_string(ARCS_PLUGIN_API_VERSION) + ")";
  });
}
