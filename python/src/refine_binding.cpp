// SPDX-License-Identifier: Apache-2.0
// okid._core.refine and RefineCore: the prediction-error refinement (okid/refine.h) of a model
// over a record the caller holds, fed once per pass from its arrays (no copy, GIL released), with
// the noise estimated or fixed (okid_refine_set_noise: the Cramer-Rao bound). The CLI's JSON
// writer gives the "refinement" object of to_dict().
#include <cstdio>  // before nanobind (binding.h says why)
#include <cstdlib>
#include <exception>
#include <memory>
#include <optional>

#include <nanobind/stl/complex.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include "binding.h"

extern "C" {
#include "config_names.h"
#include "json_writer.h"
#include "refine_choice.h"
#include "start_search.h"
}

namespace okid_py {

namespace {

struct AlignedFree {
    void operator()(void *p) const noexcept { std::free(p); }
};

using CMatrix = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using CVector = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

// A (rows, cols) C-order array copied to column-major storage.
std::vector<okid_real> column_major(const CMatrix &a)
{
    const size_t rows = a.shape(0), cols = a.shape(1);
    std::vector<okid_real> v(rows * cols);
    for (size_t i = 0; i < rows; ++i)
        for (size_t j = 0; j < cols; ++j) v[i + j * rows] = a.data()[i * cols + j];
    return v;
}

// Passes of rf over the caller's record (count samples of ru inputs and my outputs) until its state
// is not NEED_PASS, in chunks: Ctrl-C raises between two, progress(done, max_passes count) after
// each. Called with the GIL held.
int refine_passes(okid_refiner *rf, size_t count, const double *u, size_t ru, const double *y, size_t my,
                  size_t chunk, int max_passes, const nb::object &progress, okid_refine_state *state)
{
    int s = OKID_OK;
    for (int pass = 0; s == OKID_OK && *state == OKID_REFINE_NEED_PASS; ++pass) {
        s = okid_refine_begin_pass(rf);
        if (s == OKID_OK)
            s = feed_in_chunks(count, chunk, progress, (size_t)pass * count, (size_t)max_passes * count,
                               [&](size_t first, size_t rows) {
                                   return (int)okid_refine_push_block(rf, rows, u + first * ru, ru, y + first * my, my);
                               });
        if (s == OKID_OK) s = okid_refine_end_pass(rf, state);
    }
    return s;
}

// Rows per chunk of a refinement of order n with r inputs and m outputs: a sample's sensitivities
// and Gauss-Newton sums cost about P^2 m multiply-adds, P the parameters.
size_t refine_chunk_rows(int n, int r, int m, okid_refine_model model)
{
    // a sample's sensitivities and Gauss-Newton sums cost about P^2 m multiply-adds, P the parameters
    // (the innovation form's gain K adds n m)
    const double params = (double)n * (double)(r + m + 1) + (double)m * (double)r +
                          (model == OKID_REFINE_INNOVATION ? (double)n * (double)m : 0);
    return chunk_rows(params * params * (double)m);
}

// start_search_run()'s refinement of a start, as okid.Result.refine() runs it (RefineCore's settings,
// chunks), quietly. An exception (Ctrl-C) is kept for after the search, which it stops.
struct StartRecord {
    okid_refine_config cfg;
    okid_sensing sensing;
    size_t count;
    const double *u, *y;
    std::exception_ptr error;
};

int refine_start(void *context, const okid_result *start, int *state, double *cost, unsigned *warnings)
{
    auto *rec = static_cast<StartRecord *>(context);
    const int n = start->order, r = start->B.cols, mo = start->C.rows;
    size_t bytes = 0;
    if (okid_refine_model_workspace_size(rec->cfg.refine_model, n, r, mo, &bytes) != OKID_OK) return 1;
    std::unique_ptr<void, AlignedFree> ws(std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16));
    if (!ws) return 1;
    okid_refiner rf;
    okid_refine_result out;
    okid_refine_state st = OKID_REFINE_NEED_PASS;
    int s = okid_refine_init(&rf, &rec->cfg, start, rec->sensing, ws.get(), bytes, nullptr);
    nb::gil_scoped_acquire gil;
    try {
        if (s == OKID_OK)
            s = refine_passes(&rf, rec->count, rec->u, (size_t)r, rec->y, (size_t)mo,
                              refine_chunk_rows(n, r, mo, rec->cfg.refine_model),
                              rec->cfg.max_passes, nb::none(), &st);
    } catch (...) {
        rec->error = std::current_exception();
        return -1;
    }
    if (s == OKID_OK) s = okid_refine_get_result(&rf, &out);
    if (s != OKID_OK) return 1;
    *state = (int)out.state;
    *cost = (double)out.cost;
    *warnings = out.warnings;
    return 0;
}

}  // namespace

// A finished refinement: the refiner and the workspace its result's views point into.
struct RefineCore {
    std::unique_ptr<void, AlignedFree> ws;
    okid_refiner rf{};
    okid_refine_config cfg{};
    okid_refine_result out{};
    int m = 0;

    // The refined result's top-level members and ',\n  "refinement": {...}' exactly as okid
    // identify --refine --json writes them after "start".
    nb::str to_json() const
    {
        return write_to_string([this](FILE *f) { json_refined_result(f, &cfg, &out, m); });
    }

    nb::dict fields() const
    {
        nb::dict f;
        f["state"] = json_refine_state_name(out.state);
        f["message"] = okid_refine_state_str(out.state);
        f["passes"] = out.passes;
        f["iterations"] = out.iterations;
        f["num_parameters"] = out.num_parameters;
        f["order"] = out.order;
        f["samples"] = out.samples;
        f["dt"] = (double)out.dt;
        f["cost"] = (double)out.cost;
        f["decrement"] = (double)out.decrement;
        f["warnings"] = out.warnings;
        f["std_status"] = (int)out.std_status;
        f["max_passes"] = cfg.max_passes;
        f["step_tolerance"] = (double)cfg.step_tolerance;
        f["refine_model"] = cli_name_of(cli_refine_model_names, (int)cfg.refine_model);
        if (out.K.data != nullptr) {
            f["K"] = matrix_array(out.K);
        } else {
            f["K"] = nb::none();
        }
        f["A"] = matrix_array(out.A);
        f["B"] = matrix_array(out.B);
        f["C"] = matrix_array(out.C);
        f["D"] = matrix_array(out.D);
        f["initial_state"] = vector_array(out.initial_state, out.order);
        f["residual_rms_start"] = vector_array(out.residual_rms_start, m);
        f["residual_rms"] = vector_array(out.residual_rms, m);
        f["whiteness"] = vector_array(out.whiteness, m);
        f["max_autocorrelation"] = vector_array(out.max_autocorrelation, m);
        f["fit_percent"] = vector_array(out.fit_percent, m);
        const int r = out.B.cols; /* output i, input j at [i + m j]: an m x r matrix */
        f["input_correlation"] = matrix_array(okid_matrix{const_cast<okid_real *>(out.input_correlation), m, r, m});
        f["max_input_correlation"] = matrix_array(okid_matrix{const_cast<okid_real *>(out.max_input_correlation), m, r, m});
        f["input_correlation_band"] = matrix_array(okid_matrix{const_cast<okid_real *>(out.input_correlation_band), m, r, m});
        nb::list output_warnings;
        for (int i = 0; i < m; ++i) output_warnings.append(out.output_warnings[i]);
        f["output_warnings"] = output_warnings;
        f["autocorrelation_band"] = (double)out.autocorrelation_band;
        f["std_covariance"] = out.covariance == OKID_REFINE_COVARIANCE_SANDWICH ? "sandwich" : "fisher";
        if (out.split_modes[0] >= 0) {
            f["split_modes"] = nb::make_tuple(out.split_modes[0], out.split_modes[1]);
        } else {
            f["split_modes"] = nb::none();
        }
        nb::list modes;
        for (int i = 0; i < out.num_modes; ++i) {
            const okid_mode_std &sd = out.mode_std[i];
            nb::dict d = mode_dict(out.modes[i], m);
            d["frequency_std"] = (double)sd.frequency_hz;
            d["damping_std"] = (double)sd.damping_ratio;
            d["eigenvalue_std"] = std::complex<double>(sd.eigenvalue.re, sd.eigenvalue.im);
            d["pole_std"] = std::complex<double>(sd.pole.re, sd.pole.im);
            d["sensor_shape_std"] = complex_array(sd.sensor_shape, m);
            modes.append(d);
        }
        f["modes"] = modes;
        return f;
    }
};

void bind_refine(nb::module_ &m)
{
    m.def(
        "refine_config_default",
        []() {
            okid_refine_config c{};
            okid_refine_config_default(&c);
            return nb::make_tuple(c.max_passes, (double)c.step_tolerance);
        },
        "okid_refine_config_default(): (max_passes, step_tolerance).");

    nb::class_<RefineCore>(m, "RefineCore")
        .def("to_json", &RefineCore::to_json, "The \"refinement\" member of okid identify --refine --json.")
        .def("fields", &RefineCore::fields);

    m.def(
        "refine",
        [](CMatrix a, CMatrix b, CMatrix c, CMatrix d, double dt, int sensing, CMatrix u, CMatrix y,
           int max_passes, double step_tolerance, std::optional<CVector> noise_std, nb::object progress,
           int refine_model) {
            const int n = (int)a.shape(0), r = (int)b.shape(1), mo = (int)c.shape(0);
            auto core = std::make_unique<RefineCore>();
            core->m = mo;
            core->cfg.max_passes = max_passes;
            core->cfg.step_tolerance = (okid_real)step_tolerance;
            core->cfg.refine_model = (okid_refine_model)refine_model;
            size_t bytes = 0;
            int s = okid_refine_model_workspace_size(core->cfg.refine_model, n, r, mo, &bytes);
            if (s != OKID_OK) return nb::make_tuple(s, nb::none());
            core->ws.reset(std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16));
            if (!core->ws) throw std::bad_alloc();
            std::vector<okid_real> av = column_major(a), bv = column_major(b), cv = column_major(c),
                                   dv = column_major(d);
            okid_result start{};
            start.order = n;
            start.dt = (okid_real)dt;
            start.A = okid_matrix{av.data(), (int)a.shape(0), (int)a.shape(1), (int)a.shape(0)};
            start.B = okid_matrix{bv.data(), (int)b.shape(0), (int)b.shape(1), (int)b.shape(0)};
            start.C = okid_matrix{cv.data(), (int)c.shape(0), (int)c.shape(1), (int)c.shape(0)};
            start.D = okid_matrix{dv.data(), (int)d.shape(0), (int)d.shape(1), (int)d.shape(0)};
            okid_refine_state state = OKID_REFINE_NEED_PASS;
            {
                nb::gil_scoped_release release;
                s = okid_refine_init(&core->rf, &core->cfg, &start, (okid_sensing)sensing, core->ws.get(), bytes,
                                     nullptr);
                if (s == OKID_OK && noise_std) s = okid_refine_set_noise(&core->rf, noise_std->data());
            }
            // the caller's (count, r) and (count, m) arrays are the record: fed once per pass in chunks,
            // Ctrl-C raising between two; progress sees samples fed over samples x max_passes
            if (s == OKID_OK)
                s = refine_passes(&core->rf, u.shape(0), u.data(), u.shape(1), y.data(), y.shape(1),
                                  refine_chunk_rows(n, r, mo, core->cfg.refine_model), max_passes, progress, &state);
            if (s == OKID_OK) s = okid_refine_get_result(&core->rf, &core->out);
            if (s != OKID_OK) return nb::make_tuple(s, nb::none());
            return nb::make_tuple(s, nb::cast(core.release(), nb::rv_policy::take_ownership));
        },
        nb::arg("a"), nb::arg("b"), nb::arg("c"), nb::arg("d"), nb::arg("dt"), nb::arg("sensing"), nb::arg("u"),
        nb::arg("y"), nb::arg("max_passes"), nb::arg("step_tolerance"), nb::arg("noise_std").none(),
        nb::arg("progress").none() = nb::none(), nb::arg("refine_model") = 0,
        "okid_refine_init from (A, B, C, D, dt) fitting refine_model (okid_refine_model), okid_refine_set_noise when noise_std is given, then passes over "
        "(u, y) until the state is not NEED_PASS, in chunks (Ctrl-C raises between two, progress(done, "
        "max_passes count) is called after each): (status, RefineCore).");

    // refine_model = "auto" (host_tools/common/refine_choice.c, the CLI's rule): whether output
    // error's result calls for the innovation form, and the choice between the two
    m.def(
        "refine_needs_innovation", [](const RefineCore &oe) { return refine_choice_needs_innovation(&oe.out) != 0; },
        nb::arg("oe"), "refine_choice_needs_innovation(): output error's residual is not white.");
    m.def(
        "refine_choose",
        [](const RefineCore &oe, const RefineCore *inn) {
            refine_choice c{};
            refine_choose(&oe.out, inn != nullptr ? &inn->out : nullptr, oe.m, &c);
            return nb::make_tuple(std::string(okid_refine_model_str(c.chosen)),
                                  std::string(refine_choice_reason_name(c.reason)), std::string(c.detail));
        },
        nb::arg("oe"), nb::arg("inn").none(),
        "refine_choose() of output error's and (None: not run) the innovation form's refinements of one record: "
        "(chosen model, reason, detail), the CLI's refine_model_choice.");

    m.def(
        "start_search",
        [](const nb::dict &config, CMatrix u, CMatrix y, int max_passes, double step_tolerance, int refine_model) {
            okid_config cfg = config_from_dict(config);
            StartRecord rec{};
            okid_refine_config_default(&rec.cfg);
            rec.cfg.max_passes = start_search_passes(max_passes); // each start's cap (start_search.h)
            rec.cfg.step_tolerance = (okid_real)step_tolerance;
            rec.cfg.refine_model = (okid_refine_model)refine_model;
            rec.sensing = cfg.sensing;
            rec.count = u.shape(0);
            rec.u = u.data();
            rec.y = y.data();
            start_search search{};
            {
                nb::gil_scoped_release release;
                start_search_run(&cfg, rec.count, rec.u, rec.y, refine_start, &rec, &search);
            }
            if (rec.error) std::rethrow_exception(rec.error);
            nb::dict chosen;
            chosen["observer_order"] = cfg.observer_order;
            chosen["hankel_rows"] = cfg.hankel_rows;
            chosen["hankel_cols"] = cfg.hankel_cols;
            return nb::make_tuple(chosen, write_to_string([&](FILE *f) { json_start_search(f, &search); }));
        },
        nb::arg("config"), nb::arg("u"), nb::arg("y"), nb::arg("max_passes"), nb::arg("step_tolerance"),
        nb::arg("refine_model") = 0,
        "start_search_run() of the host library (host_tools/common/start_search.h), okid identify --refine's own, "
        "each start refined as refine() does, quietly: (the chosen observer_order and Hankel size, the JSON's "
        "',\\n  \"start_search\": {...}' member).");
}

}  // namespace okid_py
