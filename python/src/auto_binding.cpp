// SPDX-License-Identifier: Apache-2.0
// okid._core.auto_identify: the settings chosen from the data, the physical modes and the model, by
// the CLI's own code (host_tools/common/auto_identify.c, auto_report.c): one rule on both surfaces.
#include <cstdio>  // before nanobind (binding.h says why)
#include <cstdlib>
#include <exception>
#include <memory>

#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>

#include "binding.h"

extern "C" {
#include "auto_identify.h"
#include "auto_modes.h"
#include "auto_report.h"
#include "auto_settings.h"
#include "refine_selection.h"
}

namespace okid_py {

namespace {

using CBlock = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

struct IdentificationFree {
    void operator()(auto_identification *ai) const noexcept { auto_identification_free(ai); }
};

// The model's samples in chunks, as IdentifierCore.push_block feeds them: progress after each
// chunk, a pending signal raising between two. The exception is kept for after auto_identify()
// (it must not unwind through C), and the push then fails.
struct PushContext {
    nb::object progress;
    const okid_config *cfg;
    std::exception_ptr error;
};

okid_status push_with_progress(void *context, okid_identifier *id, size_t n, const okid_real *u, const okid_real *y)
{
    auto *push = static_cast<PushContext *>(context);
    const size_t r = (size_t)push->cfg->num_inputs, mo = (size_t)push->cfg->num_outputs;
    nb::gil_scoped_acquire gil;
    try {
        return (okid_status)feed_in_chunks(n, push_chunk_rows(*push->cfg), push->progress, 0, n,
                                           [&](size_t first, size_t count) {
                                               return (int)okid_push_block(id, count, u + first * r, r,
                                                                           y + first * mo, mo, nullptr);
                                           });
    } catch (...) {
        push->error = std::current_exception();
        return OKID_E_NOT_AVAILABLE;
    }
}


// The record and the settings given, as auto_identify() takes them (no push callback: one okid_push_block).
auto_request request_of(const nb::dict &config, unsigned given, CBlock u, CBlock y)
{
    auto_request rq{};
    rq.cfg = config_from_dict(config);
    rq.given = given;
    rq.n = u.shape(0);
    rq.u = u.data();
    rq.y = y.data();
    return rq;
}

// A selected mode: the okid_mode fields, then its cluster's statistics and its support.
nb::dict selected_dict(const auto_modes &am, const auto_choice &choice, int k, int m)
{
    const auto_mode &md = am.modes[k];
    nb::dict d = selected_mode_dict(*md.selected, am.observers[md.observer].runs[md.window].table.num_orders,
                                    md.windows, am.num_runs, m);
    d["observers"] = md.observers;
    d["of_observers"] = am.valid_observers;
    d["observer_order"] = choice.observer_orders[md.observer];
    return d;
}

}  // namespace

void bind_auto(nb::module_ &m)
{
    m.attr("AUTO_GIVEN_DECIMATION") = (unsigned)AUTO_GIVEN_DECIMATION;
    m.attr("AUTO_GIVEN_OBSERVER") = (unsigned)AUTO_GIVEN_OBSERVER;
    m.attr("AUTO_GIVEN_HANKEL") = (unsigned)AUTO_GIVEN_HANKEL;
    m.attr("AUTO_GIVEN_ALL") = (unsigned)(AUTO_GIVEN_DECIMATION | AUTO_GIVEN_OBSERVER | AUTO_GIVEN_HANKEL);
    m.def(
        "auto_identify",
        [](const nb::dict &config, unsigned given, CBlock u, CBlock y, nb::object progress) {
            auto_request rq = request_of(config, given, u, y);
            PushContext push{progress, nullptr, {}};
            rq.push = push_with_progress;
            rq.push_context = &push;
            auto_identification ai{};
            okid_status status;
            {
                nb::gil_scoped_release release;
                push.cfg = &ai.cfg;
                status = auto_identify(&rq, &ai);
            }
            std::unique_ptr<auto_identification, IdentificationFree> owner(&ai);
            if (push.error) std::rethrow_exception(push.error);  // Ctrl-C, or the progress callback's own
            if (ai.failure == AUTO_FAILED_MEMORY) throw std::bad_alloc();
            const okid_config &cfg = ai.cfg;
            const int outputs = cfg.num_outputs;
            nb::dict settings;
            settings["decimation"] = cfg.decimation;
            settings["observer_order"] = cfg.observer_order;
            settings["hankel_rows"] = cfg.hankel_rows;
            settings["hankel_cols"] = cfg.hankel_cols;
            settings["order"] = cfg.order;
            settings["estimator"] = (int)cfg.estimator;
            if (ai.failure == AUTO_FAILED_DATA) {
                return nb::make_tuple((int)status, settings, nb::str(ai.shortfall), nb::none(), nb::none(), nb::none());
            }
            if (status != OKID_OK) return nb::make_tuple((int)status, settings, nb::none(), nb::none(), nb::none(), nb::none());
            nb::str json = write_to_string(
                [&](FILE *out) { auto_json(out, &ai.choice, (double)cfg.dt, ai.modes, &ai.result, outputs); });
            nb::list selected, verdicts;
            if (ai.modes != nullptr) {
                for (int k = 0; k < ai.modes->num_modes; ++k) selected.append(selected_dict(*ai.modes, ai.choice, k, outputs));
                for (int i = 0; i < ai.result.num_modes; ++i) {
                    const char *why = auto_pole_verdict(ai.modes, &ai.result.modes[i], outputs);
                    verdicts.append(why ? nb::cast(std::string(why)) : nb::none());
                }
            }
            // the model's identifier and result: okid.identify's Result, identified once
            void *workspace = ai.workspace;
            ai.workspace = nullptr;  // the IdentifierCore's from here on
            nb::tuple model = adopt_identifier(cfg, workspace, ai.id, ai.result);
            return nb::make_tuple((int)status, settings, json, ai.modes ? nb::object(selected) : nb::none(),
                                  ai.modes ? nb::object(verdicts) : nb::none(), model);
        },
        nb::arg("config"), nb::arg("given"), nb::arg("u"), nb::arg("y"), nb::arg("progress").none() = nb::none(),
        "auto_identify() of the host library (host_tools/common/auto_identify.h), okid identify's own: (status, "
        "settings of the model, the JSON's \"chosen\"/\"modes\"/\"poles\" members (the refusal on too little "
        "data), selected modes or None, the model's pole verdicts or None, (IdentifierCore, ResultCore) or None). "
        "The model's samples go in chunks: progress(done, count) after each, Ctrl-C raises between two.");
    m.def(
        "refine_selection",
        [](const nb::dict &config, unsigned given, CBlock u, CBlock y) {
            auto_request rq = request_of(config, given, u, y);
            auto_identification ai{};
            refine_selection sel{};
            okid_status status;
            int memory = 0;
            {
                nb::gil_scoped_release release;
                status = auto_identify(&rq, &ai);
                if (status == OKID_OK) memory = refine_selection_start(&ai, &sel);
            }
            std::unique_ptr<auto_identification, IdentificationFree> owner(&ai);
            struct SelectionFree {
                void operator()(refine_selection *s) const noexcept { refine_selection_free(s); }
            };
            std::unique_ptr<refine_selection, SelectionFree> sel_owner(&sel);
            if (ai.failure == AUTO_FAILED_MEMORY || memory != 0) throw std::bad_alloc();
            if (status != OKID_OK) {
                return nb::make_tuple((int)status, 0, nb::none(), nb::none(), nb::none(), nb::none(), nb::none());
            }
            const okid_config &cfg = ai.cfg;
            nb::dict settings;
            settings["observer_order"] = cfg.observer_order;
            settings["hankel_rows"] = cfg.hankel_rows;
            settings["hankel_cols"] = cfg.hankel_cols;
            settings["estimator"] = (int)cfg.estimator;
            nb::str chosen = write_to_string([&](FILE *out) {
                auto_json_chosen(out, &ai.choice, (double)cfg.dt, sel.order, sel.reason);
            });
            if (sel.order == 0) {
                return nb::make_tuple((int)status, 0, nb::str(sel.reason), chosen, settings, nb::none(), nb::none());
            }
            nb::list poles;
            for (int k = 0; k < sel.num_modes + sel.num_other; ++k) poles.append(sel.poles[k]);
            const okid_result &s0 = sel.start;
            nb::tuple start = nb::make_tuple(matrix_array(s0.A), matrix_array(s0.B), matrix_array(s0.C),
                                             matrix_array(s0.D),
                                             s0.G.data != nullptr ? nb::cast(matrix_array(s0.G)) : nb::none(), poles);
            void *workspace = ai.workspace;
            ai.workspace = nullptr;  // the IdentifierCore's from here on
            nb::tuple model = adopt_identifier(cfg, workspace, ai.id, ai.result);
            return nb::make_tuple((int)status, sel.order, nb::str(sel.reason), chosen, settings, start, model);
        },
        nb::arg("config"), nb::arg("given"), nb::arg("u"), nb::arg("y"),
        "refine_selection_start() after auto_identify() (host_tools/common/refine_selection.h), okid identify "
        "--refine's order and start without --order: (status, order (0: none kept), reason, the JSON's "
        "\"chosen\" member, the selection's settings, (A, B, C, D, G or None, kept pole indices) or None, "
        "(IdentifierCore, ResultCore) or None).");
}

}  // namespace okid_py
