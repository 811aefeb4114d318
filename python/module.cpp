// cavesim._cavesim: the Python binding of the public C++ API (include/cavesim/cavesim.h). The
// package cavesim/__init__.py re-exports it and adds what is easier in Python (report as a dict,
// the networkx graph). Grids are NumPy views of the result's memory, shape (nz, ny, nx).
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cavesim/cavesim.h>

#include <memory>
#include <string>

namespace py = pybind11;
namespace api = cavesim::api;

namespace {

/// A Python value (bool, int, float, str, mapping, sequence, NumPy scalar or array) as a Value.
api::Value toValue(const py::handle& h) {
    if (py::isinstance<py::bool_>(h)) return api::Value(h.cast<bool>());
    if (py::isinstance<py::str>(h)) return api::Value(h.cast<std::string>());
    if (py::hasattr(h, "dtype") && py::hasattr(h, "item") && py::getattr(h, "ndim", py::int_(1)).cast<int>() == 0)
        return toValue(h.attr("item")());  // NumPy scalar
    if (py::isinstance<py::int_>(h)) return api::Value(h.cast<std::int64_t>());
    if (py::isinstance<py::float_>(h)) return api::Value(h.cast<double>());
    if (py::isinstance<py::dict>(h) || py::hasattr(h, "keys")) {
        api::Value t = api::Value::table({});
        for (const py::handle key : h.attr("keys")()) t.insert(py::str(key).cast<std::string>(), toValue(h[key]));
        return t;
    }
    if (py::hasattr(h, "tolist")) return toValue(h.attr("tolist")());  // NumPy array
    if (py::isinstance<py::sequence>(h)) {
        std::vector<api::Value> items;
        for (const py::handle e : h) items.push_back(toValue(e));
        return api::Value(std::move(items));
    }
    throw cavesim::InputError("cannot use a Python " + std::string(py::str(h.get_type().attr("__name__"))) +
                              " as a scenario value (bool, int, float, str, list or dict)");
}

py::object fromValue(const api::Value& v) {
    switch (v.kind()) {
        case api::Value::Kind::kBool:
            return py::bool_(v.asBool());
        case api::Value::Kind::kInt:
            return py::int_(v.asInt());
        case api::Value::Kind::kReal:
            return py::float_(v.asReal());
        case api::Value::Kind::kString:
            return py::str(v.asString());
        case api::Value::Kind::kList: {
            py::list l;
            for (const api::Value& e : v.items()) l.append(fromValue(e));
            return std::move(l);
        }
        case api::Value::Kind::kTable: {
            py::dict d;
            for (std::size_t n = 0; n < v.keys().size(); ++n) d[py::str(v.keys()[n])] = fromValue(v.items()[n]);
            return std::move(d);
        }
    }
    return py::none();
}

/// A read-only NumPy view of a result's grid, shape (nz, ny, nx), kept alive by `owner`.
template <typename T>
py::array gridArray(const api::GridView<T>& g, const py::object& owner) {
    const auto s = py::ssize_t(sizeof(T));
    const py::ssize_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    py::array_t<T> a({nz, ny, nx}, {s * nx * ny, s * nx, s}, g.data, owner);
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return std::move(a);
}

/// A read-only (rows, 3) NumPy view of a vector of 3-arrays, kept alive by `owner`.
template <typename T, std::size_t N>
py::array rowsArray(const std::vector<std::array<T, N>>& rows, const py::object& owner) {
    const auto s = py::ssize_t(sizeof(T));
    py::array_t<T> a({py::ssize_t(rows.size()), py::ssize_t(N)}, {s * py::ssize_t(N), s},
                     rows.empty() ? nullptr : rows.front().data(), owner);
    py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return std::move(a);
}

/// Defines `name`(first, threads, progress, cancel, mesh, analysis, stage1_state, checkpoint_path,
/// checkpoint_every): `start(first, options)` (api::run or api::resume) run without the GIL; the
/// callback takes it back, and Ctrl-C stops the run.
template <typename First, typename Start>
void defRun(py::module_& m, const char* name, const char* first, Start start) {
    m.def(
        name,
        [start](const First& x, int threads, const py::object& progress, const api::CancelToken& cancel, bool mesh,
                bool analysis, const std::string& stage1State, const std::string& checkpointPath, int checkpointEvery) {
            api::RunOptions o;
            o.threads = threads;
            o.cancel = cancel;
            o.mesh = mesh;
            o.analysis = analysis;
            o.stage1StatePath = stage1State;
            o.checkpointPath = checkpointPath;
            o.checkpointEvery = checkpointEvery;
            // By reference: the callback object outlives the run (it is the caller's argument), and a
            // copy of it must not change its reference count without the GIL.
            o.progress = [&progress](const std::string& phase, long done, long total) {
                py::gil_scoped_acquire gil;
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                if (!progress.is_none()) progress(phase, done, total);
            };
            std::shared_ptr<api::Result> result;
            {
                py::gil_scoped_release release;
                result = std::make_shared<api::Result>(start(x, o));
            }
            return result;
        },
        py::arg(first), py::arg("threads") = 0, py::arg("progress") = py::none(),
        py::arg("cancel") = api::CancelToken(), py::arg("mesh") = true, py::arg("analysis") = true,
        py::arg("stage1_state") = "", py::arg("checkpoint_path") = "", py::arg("checkpoint_every") = 0);
}

}  // namespace

PYBIND11_MODULE(_cavesim, m) {
    m.doc() = "cavesim: cave-like channel networks after Pytel & Mann (JCGT 2015), as a Python module";
    m.attr("__version__") = api::version();

    // Exceptions: the library's classes, with the command's messages. Base first (pybind11 tries the
    // translators registered last first).
    static py::exception<cavesim::Error> error(m, "Error");
    static py::exception<cavesim::InputError> inputError(m, "InputError", error.ptr());
    static py::exception<cavesim::RuntimeError> runtimeError(m, "RuntimeError", error.ptr());
    static py::exception<cavesim::InternalError> internalError(m, "InternalError", error.ptr());
    static py::exception<cavesim::Cancelled> cancelled(m, "Cancelled", error.ptr());
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const cavesim::Cancelled& e) {
            cancelled(e.what());
        } catch (const cavesim::InputError& e) {
            inputError(e.what());
        } catch (const cavesim::RuntimeError& e) {
            runtimeError(e.what());
        } catch (const cavesim::InternalError& e) {
            internalError(e.what());
        } catch (const cavesim::Error& e) {
            error(e.what());
        }
    });

    py::class_<api::Scenario>(m, "Scenario", "A validated scenario (docs/scenario-format.md).")
        .def(py::init<>(), "The built-in default scenario (the paper's Figure 10).")
        .def_static("from_toml", &api::Scenario::fromTomlFile, py::arg("path"), "Reads a scenario file.")
        .def_static("from_toml_string", &api::Scenario::fromTomlString, py::arg("text"),
                    py::arg("source_name") = "<string>", "Reads scenario text.")
        .def_static(
            "from_dict",
            [](const py::object& d, const std::string& name) { return api::Scenario::fromTable(toValue(d), name); },
            py::arg("d"), py::arg("source_name") = "<dict>",
            "A scenario from a dict shaped like a scenario file (nested tables or dotted keys).")
        .def(
            "set", [](api::Scenario& s, const std::string& key, const py::object& v) { s.set(key, toValue(v)); },
            py::arg("key"), py::arg("value"), "Sets one dotted key, or every entry of a table of arrays.")
        .def(
            "update", [](api::Scenario& s, const py::object& d) { s.update(toValue(d)); }, py::arg("values"),
            "Sets several keys at once, checked together.")
        .def(
            "add", [](api::Scenario& s, const std::string& t, const py::object& e) { s.add(t, toValue(e)); },
            py::arg("table"), py::arg("entry"), "Appends an entry to a table of arrays ('source', 'sink', …).")
        .def("clear", &api::Scenario::clear, py::arg("table"), "Removes every entry of a table of arrays.")
        .def(
            "get", [](const api::Scenario& s, const std::string& key) { return fromValue(s.get(key)); }, py::arg("key"),
            "The value of a dotted key, defaults filled in.")
        .def("__getitem__", [](const api::Scenario& s, const std::string& key) { return fromValue(s.get(key)); })
        .def("__setitem__",
             [](api::Scenario& s, const std::string& key, const py::object& v) { s.set(key, toValue(v)); })
        .def(
            "to_dict", [](const api::Scenario& s) { return fromValue(s.toTable()); },
            "The effective scenario as nested dicts, every default filled in.")
        .def("to_toml", &api::Scenario::toToml, "The effective scenario as TOML.")
        .def("copy", [](const api::Scenario& s) { return api::Scenario(s); })
        .def("__copy__", [](const api::Scenario& s) { return api::Scenario(s); })
        .def("__deepcopy__", [](const api::Scenario& s, const py::object&) { return api::Scenario(s); })
        .def_property_readonly("name", &api::Scenario::name)
        .def_property_readonly("seed", &api::Scenario::seed)
        .def_property_readonly("size", &api::Scenario::size, "(nx, ny, nz) voxels")
        .def_property_readonly("voxel_size", &api::Scenario::voxelSize, "metres")
        .def_property_readonly("source_name", &api::Scenario::sourceName)
        .def_static("keys", &api::Scenario::keys, "Every settable key, dotted.")
        .def("__repr__", [](const api::Scenario& s) {
            const auto n = s.size();
            return "<cavesim.Scenario '" + s.name() + "' " + std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" +
                   std::to_string(n[2]) + " from " + s.sourceName() + ">";
        });

    py::class_<api::CancelToken>(m, "CancelToken", "Cancels a run from another thread or from the progress callback.")
        .def(py::init<>())
        .def("cancel", &api::CancelToken::cancel)
        .def_property_readonly("cancelled", &api::CancelToken::cancelled);

    py::class_<api::Result, std::shared_ptr<api::Result>>(m, "_Result")
        .def_property_readonly("dims", &api::Result::dims, "(nx, ny, nz)")
        .def_property_readonly("voxel_size", &api::Result::voxelSize)
        .def_property_readonly(
            "porosity", [](const py::object& r) { return gridArray(r.cast<const api::Result&>().porosity(), r); })
        .def_property_readonly(
            "porosity0", [](const py::object& r) { return gridArray(r.cast<const api::Result&>().porosity0(), r); })
        .def_property_readonly(
            "pressure", [](const py::object& r) { return gridArray(r.cast<const api::Result&>().pressure(), r); })
        .def_property_readonly("flow",
                               [](const py::object& r) { return gridArray(r.cast<const api::Result&>().flow(), r); })
        .def_property_readonly("water",
                               [](const py::object& r) { return gridArray(r.cast<const api::Result&>().water(), r); })
        .def_property_readonly("flags",
                               [](const py::object& r) { return gridArray(r.cast<const api::Result&>().flags(), r); })
        .def_property_readonly("zone",
                               [](const py::object& r) { return gridArray(r.cast<const api::Result&>().zone(), r); })
        .def_property_readonly(
            "cave_mask", [](const py::object& r) { return gridArray(r.cast<const api::Result&>().caveMask(), r); })
        .def_property_readonly(
            "mesh_vertices",
            [](const py::object& r) { return rowsArray(r.cast<const api::Result&>().mesh().vertices, r); })
        .def_property_readonly(
            "mesh_normals",
            [](const py::object& r) { return rowsArray(r.cast<const api::Result&>().mesh().normals, r); })
        .def_property_readonly(
            "mesh_faces",
            [](const py::object& r) { return rowsArray(r.cast<const api::Result&>().mesh().triangles, r); })
        .def_property_readonly("skeleton_positions",
                               [](const api::Result& r) {
                                   const auto& nodes = r.skeleton().nodes;
                                   py::array_t<double> a({py::ssize_t(nodes.size()), py::ssize_t(3)});
                                   auto w = a.mutable_unchecked<2>();
                                   for (std::size_t n = 0; n < nodes.size(); ++n)
                                       for (int c = 0; c < 3; ++c) w(py::ssize_t(n), c) = nodes[n].position[c];
                                   return a;
                               })
        .def_property_readonly("skeleton_radii",
                               [](const api::Result& r) {
                                   const auto& nodes = r.skeleton().nodes;
                                   py::array_t<double> a(py::ssize_t(nodes.size()));
                                   auto w = a.mutable_unchecked<1>();
                                   for (std::size_t n = 0; n < nodes.size(); ++n) w(py::ssize_t(n)) = nodes[n].radius;
                                   return a;
                               })
        .def_property_readonly("skeleton_voxels",
                               [](const api::Result& r) {
                                   const auto& nodes = r.skeleton().nodes;
                                   py::array_t<std::int32_t> a({py::ssize_t(nodes.size()), py::ssize_t(3)});
                                   auto w = a.mutable_unchecked<2>();
                                   for (std::size_t n = 0; n < nodes.size(); ++n)
                                       for (int c = 0; c < 3; ++c) w(py::ssize_t(n), c) = nodes[n].voxel[c];
                                   return a;
                               })
        .def_property_readonly(
            "skeleton_edges",
            [](const py::object& r) { return rowsArray(r.cast<const api::Result&>().skeleton().edges, r); })
        .def_property_readonly("report_json", [](const api::Result& r) { return r.report().json; })
        .def_property_readonly("scenario", &api::Result::scenario)
        .def("write_state", &api::Result::writeState, py::arg("path"),
             "Writes state.vdb as `cavesim run` does (byte for byte the same file).");

    defRun<api::Scenario>(m, "_run", "scenario", [](const api::Scenario& scenario, const api::RunOptions& o) {
        return api::run(scenario, o);
    });
    defRun<std::string>(m, "_resume", "path",
                        [](const std::string& path, const api::RunOptions& o) { return api::resume(path, o); });

    m.attr("FLAG_SOURCE") = int(api::kFlagSource);
    m.attr("FLAG_SINK") = int(api::kFlagSink);
    m.attr("FLAG_PROTOCHANNEL") = int(api::kFlagProtochannel);
    m.attr("FLAG_CHANNEL") = int(api::kFlagChannel);
    m.attr("FLAG_OBSTACLE") = int(api::kFlagObstacle);
    m.attr("FLAG_FRACTURE") = int(api::kFlagFracture);
    m.attr("FLAG_FEATURE_CHANNEL") = int(api::kFlagFeatureChannel);
    m.attr("FLAG_INERT") = int(api::kFlagInert);
}
