// SPDX-License-Identifier: Apache-2.0
// okid._core.auto_identify: the settings chosen from the data and the physical modes, by the CLI's
// own code (host_tools/common/auto_settings.c, auto_modes.c, auto_report.c): one rule on both surfaces.
#include <cstdio>  // before nanobind (binding.h says why)
#include <cstdlib>
#include <memory>

#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>

#include "binding.h"

extern "C" {
#include "auto_modes.h"
#include "auto_report.h"
#include "auto_settings.h"
#include "config_explain.h"
#include "json_writer.h"
}

namespace okid_py {

namespace {

using CBlock = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

struct ModesDeleter {
    void operator()(auto_modes *am) const noexcept
    {
        auto_modes_free(am);
        std::free(am);
    }
};


// A selected mode: the okid_mode fields, then its cluster's statistics and its support.
nb::dict selected_dict(const auto_modes &am, int k, int m)
{
    const okid_selected_mode *s = am.modes[k].selected;
    nb::dict d = mode_dict(s->mode, m);
    d["order"] = s->order;
    d["num_orders"] = s->num_orders;
    d["of_orders"] = am.runs[am.modes[k].window].table.num_orders;
    d["lowest_order"] = s->lowest_order;
    d["highest_order"] = s->highest_order;
    d["frequency_mean"] = (double)s->frequency_mean;
    d["frequency_std"] = (double)s->frequency_std;
    d["frequency_min"] = (double)s->frequency_min;
    d["frequency_max"] = (double)s->frequency_max;
    d["damping_mean"] = (double)s->damping_mean;
    d["damping_std"] = (double)s->damping_std;
    d["damping_min"] = (double)s->damping_min;
    d["damping_max"] = (double)s->damping_max;
    d["cmi_min"] = (double)s->cmi_min;
    d["windows"] = am.modes[k].windows;
    d["of_windows"] = am.num_runs;
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
        [](const nb::dict &config, unsigned given, CBlock u, CBlock y) {
            okid_config cfg = config_from_dict(config);
            const size_t n = u.shape(0);
            const int r = cfg.num_inputs, outputs = cfg.num_outputs;
            auto_choice choice{};
            std::unique_ptr<auto_modes, ModesDeleter> am;
            std::unique_ptr<void, decltype(&std::free)> ws(nullptr, &std::free);
            okid_identifier id;
            okid_result res{};
            int status = OKID_OK;
            char shortfall[512] = "";
            {
                nb::gil_scoped_release release;
                auto_band band{}, input_band{};
                if (auto_channel_band(y.data(), n, outputs, (double)cfg.dt, &band) != 0 ||
                    auto_channel_band(u.data(), n, r, (double)cfg.dt, &input_band) != 0) {
                    band = auto_band{0, 0, 0};
                }
                auto_choose(&cfg, given, n, &band, &choice);
                choice.given = given;
                size_t bytes = 0;
                status = okid_workspace_size(&cfg, &bytes);
                /* the data's sufficiency before any workspace (the CLI's rule) */
                if (status == OKID_OK && config_data_shortfall(&cfg, n, shortfall, sizeof shortfall)) {
                    status = OKID_E_NOT_ENOUGH_DATA;
                }
                if (status == OKID_OK && cfg.order == 0) {
                    am.reset(static_cast<auto_modes *>(std::calloc(1, sizeof(auto_modes))));
                    if (!am) throw std::bad_alloc();
                    status = auto_modes_find(&choice, &cfg, n, u.data(), y.data(), am.get());
                    if (status == OKID_OK) cfg.order = am->num_modes > 0 ? am->order : am->runs[0].result.order;
                }
                // the final model, for the JSON's "poles" (the Python layer identifies it again, bit for bit)
                if (status == OKID_OK) status = okid_workspace_size(&cfg, &bytes);
                if (status == OKID_OK) {
                    ws.reset(std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16));
                    if (!ws) throw std::bad_alloc();
                    status = okid_init(&id, &cfg, ws.get(), bytes, nullptr);
                }
                if (status == OKID_OK) status = okid_push_block(&id, n, u.data(), (size_t)r, y.data(), (size_t)outputs, nullptr);
                if (status == OKID_OK) status = okid_identify(&id, &res);
            }
            nb::dict settings;
            settings["decimation"] = cfg.decimation;
            settings["observer_order"] = cfg.observer_order;
            settings["hankel_rows"] = cfg.hankel_rows;
            settings["hankel_cols"] = cfg.hankel_cols;
            settings["order"] = cfg.order;
            if (status == OKID_E_NOT_ENOUGH_DATA && shortfall[0] != '\0') {
                return nb::make_tuple(status, settings, nb::str(shortfall), nb::none(), nb::none());
            }
            if (status != OKID_OK) return nb::make_tuple(status, settings, nb::none(), nb::none(), nb::none());
            nb::str json = write_to_string(
                [&](FILE *out) { auto_json(out, &choice, (double)cfg.dt, am.get(), &res, outputs); });
            nb::list selected, verdicts;
            if (am) {
                for (int k = 0; k < am->num_modes; ++k) selected.append(selected_dict(*am, k, outputs));
                for (int i = 0; i < res.num_modes; ++i) {
                    const char *why = auto_pole_verdict(am.get(), &res.modes[i], outputs);
                    verdicts.append(why ? nb::cast(std::string(why)) : nb::none());
                }
            }
            return nb::make_tuple(status, settings, json, am ? nb::object(selected) : nb::none(),
                                  am ? nb::object(verdicts) : nb::none());
        },
        "Settings from the data and the physical modes, by the CLI's rules: (status, settings, json, "
        "selected modes or None, the final model's pole verdicts or None).");
}

}  // namespace okid_py
