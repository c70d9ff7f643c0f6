// SPDX-License-Identifier: Apache-2.0
// okid._core.Identifier, Result and Stabilization: the identifier over a workspace it owns, each
// result copied out of the workspace (a Result outlives the next identify()), and the CLI's JSON
// writer for to_dict(). Every call returns its okid_status; okid/_identifier.py raises.
#include <cstdio>  // before nanobind (binding.h says why)
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>
#include <optional>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/complex.h>
#include <nanobind/stl/tuple.h>

#include "binding.h"

extern "C" {
#include "json_writer.h"
#include "okid_fields.h"
#include "output_fit.h"
}

namespace okid_py {

static_assert(sizeof(okid_real) == sizeof(double), "the Python package needs the double build of the core");

namespace {

struct AlignedFree {
    void operator()(void *p) const noexcept { std::free(p); }
};
using Workspace = std::unique_ptr<void, AlignedFree>;

Workspace allocate_workspace(size_t bytes)
{
    void *p = std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    if (p == nullptr) throw std::bad_alloc();
    return Workspace(p);
}

// A matrix view copied to column-major storage with leading dimension rows.
std::vector<okid_real> compact(okid_matrix m)
{
    std::vector<okid_real> v((size_t)m.rows * (size_t)m.cols);
    for (int j = 0; j < m.cols; ++j)
        for (int i = 0; i < m.rows; ++i) v[(size_t)i + (size_t)j * (size_t)m.rows] = okid_matrix_at(m, i, j);
    return v;
}

}  // namespace

nb::dict mode_dict(const okid_mode &md, int m)
{
    nb::dict d;
#define COMPLEX(name) d[#name] = std::complex<double>(md.name.re, md.name.im);
#define REAL(name) d[#name] = (double)md.name;
#define FLAG(name) d[#name] = md.name != 0;
#define SHAPE(name, k) d[#name] = complex_array(md.name, (k) * m);
    OKID_MODE_FIELDS(COMPLEX, REAL, FLAG, SHAPE)
#undef COMPLEX
#undef REAL
#undef FLAG
#undef SHAPE
    return d;
}

nb::dict selected_mode_dict(const okid_selected_mode &s, int of_orders, int windows, int of_windows, int m)
{
    nb::dict d = mode_dict(s.mode, m);
    d["order"] = s.order;
    d["num_orders"] = s.num_orders;
    d["of_orders"] = of_orders;
    d["lowest_order"] = s.lowest_order;
    d["highest_order"] = s.highest_order;
    d["frequency_mean"] = (double)s.frequency_mean;
    d["frequency_std"] = (double)s.frequency_std;
    d["frequency_min"] = (double)s.frequency_min;
    d["frequency_max"] = (double)s.frequency_max;
    d["damping_mean"] = (double)s.damping_mean;
    d["damping_std"] = (double)s.damping_std;
    d["damping_min"] = (double)s.damping_min;
    d["damping_max"] = (double)s.damping_max;
    d["cmi_min"] = (double)s.cmi_min;
    d["windows"] = windows;
    d["of_windows"] = of_windows;
    return d;
}

// An okid_result copied out of the workspace, with its views pointing into its own storage.
struct ResultCore {
    okid_config cfg{};
    okid_result res{};
    std::vector<okid_real> a, b, c, d, g, sv, markov, markov_obs, in_scales, out_scales;
    std::vector<okid_mode> modes;
    std::vector<okid_complex> shapes;

    ResultCore(const okid_config &config, const okid_result &r) : cfg(config), res(r)
    {
        auto copy = [](okid_matrix m, std::vector<okid_real> &store, okid_matrix &view) {
            if (m.data == nullptr) {
                view = okid_matrix{nullptr, m.rows, m.cols, m.ld};
                return;
            }
            store = compact(m);
            view = okid_matrix{store.data(), m.rows, m.cols, m.rows > 0 ? m.rows : 1};
        };
        copy(r.A, a, res.A);
        copy(r.B, b, res.B);
        copy(r.C, c, res.C);
        copy(r.D, d, res.D);
        copy(r.G, g, res.G);
        copy(r.markov, markov, res.markov);
        copy(r.observer_gain_markov, markov_obs, res.observer_gain_markov);
        sv.assign(r.singular_values, r.singular_values + r.num_singular_values);
        res.singular_values = sv.data();
        if (r.input_scales != nullptr) {
            in_scales.assign(r.input_scales, r.input_scales + cfg.num_inputs);
            out_scales.assign(r.output_scales, r.output_scales + cfg.num_outputs);
            res.input_scales = in_scales.data();
            res.output_scales = out_scales.data();
        }
        const size_t m = (size_t)cfg.num_outputs;
        modes.assign(r.modes, r.modes + r.num_modes);
        shapes.resize(modes.size() * 3 * m);
        for (size_t i = 0; i < modes.size(); ++i) {
            okid_complex *sensor = &shapes[i * 3 * m], *shape = sensor + m;
            std::copy(r.modes[i].sensor_shape, r.modes[i].sensor_shape + m, sensor);
            std::copy(r.modes[i].shape, r.modes[i].shape + 2 * m, shape);
            modes[i].sensor_shape = sensor;
            modes[i].shape = shape;
        }
        res.modes = modes.data();
    }

    std::vector<double> fit;  // output_fit.h over the record okid.identify() was given, else empty

    nb::str to_json() const
    {
        return write_to_string([this](FILE *out) {
            json_result(out, &cfg, &res, nullptr, nullptr, -1);
            if (!fit.empty()) json_output_fit(out, fit.data(), cfg.num_outputs);
            std::fputs("\n}\n", out);
        });
    }

    // The fit of each output over the record (u, y), as okid identify reports it, and its warning
    // into res.warnings. False when none is computed (a decimated model).
    bool measure_fit(const double *u, const double *y, size_t count)
    {
        std::vector<double> values((size_t)cfg.num_outputs);
        unsigned warning = 0;
        if (output_fit_record(&res, count, u, y, values.data(), &warning) != 0) return false;
        fit = std::move(values);
        res.warnings |= warning;
        return true;
    }

    // okid identify --refine --json's opening (the run's settings and sizes) and "start" (this
    // model): the refined result's members follow (RefineCore::to_json).
    nb::str to_json_refined_start() const
    {
        return write_to_string([this](FILE *out) {
            json_result_header(out, &cfg, &res, nullptr, nullptr, -1);
            json_start(out, &cfg, &res);
        });
    }

    // Everything but the JSON, for okid.Result.
    nb::dict fields() const
    {
        nb::dict f;
#define SCALAR(name) f[#name] = res.name;
#define REAL(name) f[#name] = (double)res.name;
        OKID_RESULT_SCALARS(SCALAR, REAL, SCALAR)
#undef SCALAR
#undef REAL
        f["A"] = matrix_array(res.A);
        f["B"] = matrix_array(res.B);
        f["C"] = matrix_array(res.C);
        f["D"] = matrix_array(res.D);
        f["G"] = res.G.data ? nb::cast(matrix_array(res.G)) : nb::none();
        f["singular_values"] = vector_array(res.singular_values, res.num_singular_values);
        f["markov"] = matrix_array(res.markov);
        f["observer_gain_markov"] =
            res.observer_gain_markov.data ? nb::cast(matrix_array(res.observer_gain_markov)) : nb::none();
        f["warnings"] = res.warnings;
        f["fit_percent"] = fit.empty() ? nb::none() : nb::cast(vector_array(fit.data(), cfg.num_outputs));
        f["input_scales"] = res.input_scales ? nb::cast(vector_array(res.input_scales, cfg.num_inputs)) : nb::none();
        f["output_scales"] =
            res.output_scales ? nb::cast(vector_array(res.output_scales, cfg.num_outputs)) : nb::none();
        nb::list ms;
        for (const okid_mode &md : modes) ms.append(mode_dict(md, cfg.num_outputs));
        f["modes"] = ms;
        return f;
    }
};

// A stabilization diagram with the workspace its views point into.
struct StabilizationCore {
    Workspace ws;
    okid_stabilization st{};
    int max_order = 0, step = 0, m = 0;

    // ',\n  "stabilization": {...}' as json_stabilization writes it (okid.Stabilization keeps the object).
    nb::str to_json() const
    {
        return write_to_string([this](FILE *out) { json_stabilization(out, &st, max_order, step, m); });
    }

    nb::list orders() const
    {
        nb::list out;
        for (int i = 0; i < st.num_orders; ++i) {
            const okid_stabilization_order &o = st.orders[i];
            nb::list modes, flags;
            for (int k = 0; k < o.num_modes; ++k) {
                modes.append(mode_dict(st.modes[o.first + k], m));
                flags.append(st.stability[o.first + k]);
            }
            out.append(nb::make_tuple(o.order, modes, flags));
        }
        return out;
    }
};

struct IdentifierCore {
    okid_config cfg{};
    Workspace ws;
    okid_identifier id{};
    std::atomic<bool> busy{false};
    uint64_t generation = 0;  // changes at every successful identify() and reset()

    // okid_workspace_size() and okid_init(); the status says why not.
    int init(const okid_config &config)
    {
        cfg = config;
        size_t bytes = 0;
        okid_status s = okid_workspace_size(&cfg, &bytes);
        if (s != OKID_OK) return s;
        ws = allocate_workspace(bytes);
        return okid_init(&id, &cfg, ws.get(), bytes, nullptr);
    }
};

using CBlock = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using CVector = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

nb::tuple adopt_identifier(const okid_config &cfg, void *workspace, const okid_identifier &id, const okid_result &res)
{
    Workspace owned(workspace);
    auto core = std::make_unique<IdentifierCore>();
    auto copy = std::make_unique<ResultCore>(cfg, res);
    core->cfg = cfg;
    core->ws = std::move(owned);
    core->id = id;  // its views point into the workspace, never into itself
    core->generation = 1;
    return nb::make_tuple(nb::cast(core.release(), nb::rv_policy::take_ownership),
                          nb::cast(copy.release(), nb::rv_policy::take_ownership));
}

okid_config config_from_dict(const nb::dict &d)
{
    okid_config c{};
    okid_config_default(&c, 1, 1);
#define INT(name) c.name = nb::cast<int>(d[#name]);
#define REAL(name) c.name = (okid_real)nb::cast<double>(d[#name]);
#define ENUM(name, type) c.name = (type)nb::cast<int>(d[#name]);
    OKID_CONFIG_FIELDS(INT, REAL, ENUM, INT)
#undef INT
#undef REAL
#undef ENUM
    return c;
}

static nb::dict config_to_dict(const okid_config &c)
{
    nb::dict d;
#define INT(name) d[#name] = c.name;
#define REAL(name) d[#name] = (double)c.name;
#define ENUM(name, type) d[#name] = (int)c.name;
    OKID_CONFIG_FIELDS(INT, REAL, ENUM, INT)
#undef INT
#undef REAL
#undef ENUM
    return d;
}

void bind_identifier(nb::module_ &m)
{
    // The field tables (okid_fields.h, okid/modal.h) for okid/_config.py, _result.py and _mode.py.
    nb::list config_fields, result_scalars, mode_fields;
#define C_INT(name) config_fields.append(nb::make_tuple(#name, "int"));
#define C_REAL(name) config_fields.append(nb::make_tuple(#name, "real"));
#define C_ENUM(name, type) config_fields.append(nb::make_tuple(#name, "enum"));
#define C_FLAG(name) config_fields.append(nb::make_tuple(#name, "flag"));
#define R_NAME(name) result_scalars.append(#name);
#define M_NAME(name) mode_fields.append(#name);
#define M_SHAPE(name, k) mode_fields.append(#name);
    OKID_CONFIG_FIELDS(C_INT, C_REAL, C_ENUM, C_FLAG)
    OKID_RESULT_SCALARS(R_NAME, R_NAME, R_NAME)
    OKID_MODE_FIELDS(M_NAME, M_NAME, M_NAME, M_SHAPE)
#undef C_INT
#undef C_REAL
#undef C_ENUM
#undef C_FLAG
#undef R_NAME
#undef M_NAME
#undef M_SHAPE
    m.attr("CONFIG_FIELDS") = nb::tuple(config_fields);
    m.attr("RESULT_SCALARS") = nb::tuple(result_scalars);
    m.attr("MODE_FIELDS") = nb::tuple(mode_fields);
    m.def(
        "config_default",
        [](int r, int mo) {
            okid_config c{};
            okid_config_default(&c, r, mo);
            return config_to_dict(c);
        },
        "okid_config_default(r, m) as a dict of the okid_config fields (enumerations as their C values).");
    m.def(
        "workspace_size",
        [](const nb::dict &d) {
            okid_config c = config_from_dict(d);
            size_t bytes = 0;
            const int s = okid_workspace_size(&c, &bytes);
            return nb::make_tuple(s, bytes);
        },
        "okid_workspace_size: (status, bytes).");

    nb::class_<ResultCore>(m, "ResultCore")
        .def("to_json", &ResultCore::to_json, "The CLI's `okid identify --json` object for this result.")
        .def("to_json_refined_start", &ResultCore::to_json_refined_start,
             "okid identify --refine --json's opening members and \"start\" (this result).")
        .def("fields", &ResultCore::fields)
        .def(
            "measure_fit",
            [](ResultCore &self, CBlock u, CBlock y) {
                nb::gil_scoped_release release;
                return self.measure_fit(u.data(), y.data(), u.shape(0));
            },
            "output_fit_record() over the record (u, y) (the fit of each output, percent, as MATLAB's compare), kept "
            "for fields() and to_json(), its warning into the result's: False when none (a decimated model, or "
            "one with a pole on or outside the unit circle).")
        .def(
            "fit_missing",
            [](const ResultCore &self) -> std::optional<std::string> {
                char message[320];
                if (!output_fit_missing(self.res.decimation, output_fit_largest_radius(&self.res), message,
                                        sizeof message)) {
                    return std::nullopt;
                }
                return std::string(message);
            },
            "Why measure_fit() computes no fit for this model (output_fit_missing), else None.");

    nb::class_<StabilizationCore>(m, "StabilizationCore")
        .def("to_json", &StabilizationCore::to_json)
        .def("orders", &StabilizationCore::orders)
        .def_prop_ro("rank_limit", [](const StabilizationCore &s) { return s.st.rank_limit; });

    nb::class_<IdentifierCore>(m, "IdentifierCore")
        .def(nb::init<>())
        .def("init", [](IdentifierCore &self, const nb::dict &d) { return self.init(config_from_dict(d)); })
        .def_prop_ro("generation", [](const IdentifierCore &self) { return self.generation; })
        .def(
            "push_block",
            [](IdentifierCore &self, CBlock u, CBlock y, nb::object progress) {
                UseGuard guard(self.busy);
                if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, (size_t)0);
                size_t accepted = 0;
                const size_t r = u.shape(1), mo = y.shape(1);
                // in chunks: Ctrl-C raises between two (the rows pushed so far stay pushed)
                const int s = feed_in_chunks(u.shape(0), push_chunk_rows(self.cfg), progress, 0, u.shape(0),
                                             [&](size_t first, size_t count) {
                    size_t taken = 0;
                    const int st = okid_push_block(&self.id, count, u.data() + first * r, r, y.data() + first * mo,
                                                   mo, &taken);
                    accepted += taken;
                    return st;
                });
                return nb::make_tuple(s, accepted);
            },
            nb::arg("u"), nb::arg("y"), nb::arg("progress").none() = nb::none(),
            "okid_push_block on a (count, r) and a (count, m) C-contiguous block, no copy, in chunks of chunk_rows() "
            "rows with signals checked and progress(done, count) called between them: (status, accepted).")
        .def("push",
             [](IdentifierCore &self, CVector u, CVector y) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return STATUS_BUSY;
                 return (int)okid_push(&self.id, u.data(), y.data());
             })
        .def("identify",
             [](IdentifierCore &self) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, nb::none());
                 okid_result res;
                 int s;
                 std::unique_ptr<ResultCore> copy;
                 {
                     nb::gil_scoped_release release;
                     s = okid_identify(&self.id, &res);
                     if (s == OKID_OK) copy = std::make_unique<ResultCore>(self.cfg, res);
                 }
                 if (s != OKID_OK) return nb::make_tuple(s, nb::none());
                 ++self.generation;
                 return nb::make_tuple(s, nb::cast(copy.release(), nb::rv_policy::take_ownership));
             })
        .def("predict",
             [](IdentifierCore &self, CVector u) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, nb::none());
                 std::vector<double> y((size_t)self.cfg.num_outputs);
                 const int s = okid_predict(&self.id, u.data(), y.data());
                 if (s != OKID_OK) return nb::make_tuple(s, nb::none());
                 const size_t mo = y.size();
                 return nb::make_tuple(s, nb::cast(owned_array(std::move(y), {mo})));
             })
        .def("reset",
             [](IdentifierCore &self) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return STATUS_BUSY;
                 ++self.generation;
                 return (int)okid_reset(&self.id);
             })
        .def("set_scales",
             [](IdentifierCore &self, CVector in, CVector out) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return STATUS_BUSY;
                 return (int)okid_set_scales(&self.id, in.data(), out.data());
             })
        .def("progress",
             [](IdentifierCore &self) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, 0, 0, 0, 0);
                 okid_progress p{};
                 const int s = okid_get_progress(&self.id, &p);
                 return nb::make_tuple(s, p.samples, p.rejected, p.rows, p.rows_needed);
             })
        .def(
            "stabilization",
            [](IdentifierCore &self, uint64_t generation, int max_order, int step, double frequency_tolerance,
               double damping_tolerance, double mac_min) {
                UseGuard guard(self.busy);
                if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, nb::none());
                if (generation != self.generation) return nb::make_tuple((int)OKID_E_NOT_AVAILABLE, nb::none());
                size_t bytes = 0;
                int s = okid_stabilization_workspace_size(&self.id, max_order, step, &bytes);
                if (s != OKID_OK) return nb::make_tuple(s, nb::none());
                auto core = std::make_unique<StabilizationCore>();
                core->ws = allocate_workspace(bytes);
                core->max_order = max_order;
                core->step = step;
                core->m = self.cfg.num_outputs;
                const okid_stabilization_criteria criteria{(okid_real)frequency_tolerance,
                                                           (okid_real)damping_tolerance, (okid_real)mac_min};
                {
                    nb::gil_scoped_release release;
                    s = okid_stabilization_compute(&self.id, max_order, step, &criteria, core->ws.get(), bytes,
                                                   &core->st);
                }
                if (s != OKID_OK) return nb::make_tuple(s, nb::none());
                return nb::make_tuple(s, nb::cast(core.release(), nb::rv_policy::take_ownership));
            },
            "okid_stabilization_compute for the result of the given generation: (status, StabilizationCore).");
}

}  // namespace okid_py
