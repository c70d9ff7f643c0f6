// SPDX-License-Identifier: Apache-2.0
// okid._core.ambient_identify: output-only identification (okid/ambient.h) of a whole record, as
// okid identify --inputs 0 runs it (host_tools/common/ambient_settings.h: the mean removed, L
// chosen from the band when not given). The record is copied and its mean removed (the caller's
// array is never written), or with L and the order given streamed through a small buffer minus the
// means (the same values), and fed in chunks with the GIL released; okid/_ambient.py turns the status into an
// exception and the dict into an okid.AmbientResult.
#include <cstdio>  // before nanobind (binding.h says why)
#include <atomic>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "binding.h"

extern "C" {
#include "ambient_modes.h"
#include "ambient_settings.h"
#include "okid_fields.h"
}

namespace okid_py {

namespace {

using CBlock = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

struct AlignedFree {
    void operator()(void *p) const noexcept { std::free(p); }
};

// The result's members, copied out of the workspace.
nb::dict result_dict(const okid_ambient_result &res, int m, int hankel_rows, double band_hz)
{
    nb::dict d;
#define INT(name) d[#name] = res.name;
#define REAL(name) d[#name] = (double)res.name;
#define COUNT(name) d[#name] = (unsigned long long)res.name;
    OKID_AMBIENT_RESULT_SCALARS(INT, REAL, COUNT)
#undef INT
#undef REAL
#undef COUNT
    nb::list modes;
    for (int i = 0; i < res.num_modes; ++i) modes.append(mode_dict(res.modes[i], m));
    d["modes"] = modes;
    d["A"] = matrix_array(res.A);
    d["C"] = matrix_array(res.C);
    d["G"] = matrix_array(res.G);
    d["correlations"] = matrix_array(res.correlations);
    d["singular_values"] = vector_array(res.singular_values, res.num_singular_values);
    d["frequency_std"] = res.frequency_std ? nb::cast(vector_array(res.frequency_std, res.num_modes)) : nb::none();
    d["damping_std"] = res.damping_std ? nb::cast(vector_array(res.damping_std, res.num_modes)) : nb::none();
    d["hankel_rows"] = hankel_rows;
    d["band_hz"] = band_hz;
    return d;
}

// A physical mode of the selection: the okid_mode fields, its cluster's statistics, its support (okid.SelectedMode).
nb::dict selected_dict(const ambient_modes &am, int k, int m)
{
    const auto_mode &md = am.modes[k];
    return selected_mode_dict(*md.selected, am.runs[md.window].table.num_orders, md.windows, am.num_runs, m);
}

// The selection's JSON ("chosen", "modes", "poles"), its physical modes and the verdict of each pole of res, into
// d; none found: OKID_W_NO_PHYSICAL_MODE in its warnings, as the identifier FMU sets it.
void modes_into(nb::dict &d, const ambient_modes &am, const okid_ambient_result &res, int m)
{
    if (am.num_modes == 0) d["warnings"] = res.warnings | (unsigned)OKID_W_NO_PHYSICAL_MODE;
    d["auto_json"] = write_to_string([&](FILE *out) { ambient_modes_json(out, &am, &res, m); });
    nb::list selected, verdicts;
    for (int k = 0; k < am.num_modes; ++k) selected.append(selected_dict(am, k, m));
    for (int i = 0; i < res.num_modes; ++i) {
        const char *why = ambient_pole_verdict(&am, &res.modes[i], m);
        verdicts.append(why ? nb::cast(std::string(why)) : nb::none());
    }
    d["selected"] = selected;
    d["verdicts"] = verdicts;
}

struct ModesFree {
    void operator()(ambient_modes *am) const noexcept
    {
        ambient_modes_free(am);
        std::free(am);
    }
};

// The configuration of m outputs with these settings (the C names), checked: a status and issue.
int build_config(int m, double dt, int hankel_rows, int order, const std::vector<int> &references, int sensing,
                 int segments, int segment_samples, okid_ambient_config *cfg, okid_config_issue *issue)
{
    okid_ambient_config_default(cfg, m >= 1 ? m : 1);
    cfg->num_outputs = m;
    cfg->dt = (okid_real)dt;
    cfg->hankel_rows = hankel_rows;
    cfg->order = order;
    cfg->sensing = (okid_sensing)sensing;
    cfg->segments = segments;
    cfg->segment_samples = segment_samples;
    cfg->num_references = (int)references.size();
    for (size_t l = 0; l < references.size() && l < (size_t)OKID_MAX_DIMENSION; ++l)
        cfg->reference_channels[l] = references[l];
    *issue = okid_config_issue{};
    const int status = m >= 1 && m <= OKID_MAX_DIMENSION && references.size() <= (size_t)m
                           ? (int)okid_ambient_config_check(cfg, issue)
                           : (int)OKID_E_BAD_SIZE;
    if (status == OKID_E_BAD_SIZE && issue->field == nullptr) {
        *issue = okid_config_issue{"num_outputs", (double)m, 1, (double)OKID_MAX_DIMENSION};
    }
    return status;
}

// (status, field, value, min, max, rest): the refused setting for okid/_ambient.py's message.
nb::tuple refusal(int status, const okid_config_issue &issue, nb::object rest)
{
    return nb::make_tuple(status, std::string(issue.field ? issue.field : ""), issue.value, issue.min, issue.max,
                          rest);
}

// Multiply-adds per sample of the sums: the work chunk_rows() divides.
double work_per_sample(const okid_ambient_config &cfg)
{
    const int nref = cfg.num_references > 0 ? cfg.num_references : cfg.num_outputs;
    return (double)cfg.num_outputs * (double)nref * (2.0 * cfg.hankel_rows + 1.0);
}

// okid.AmbientIdentifier's core: one okid_ambient over its own workspace, fed block by block.
struct AmbientCore {
    okid_ambient_config cfg{};
    std::unique_ptr<void, AlignedFree> workspace;
    size_t bytes = 0;
    okid_ambient amb{};
    std::atomic<bool> busy{false};
};

}  // namespace

void bind_ambient(nb::module_ &m)
{
    nb::list config_fields;
#define C_INT(name) config_fields.append(nb::make_tuple(#name, "int"));
#define C_REAL(name) config_fields.append(nb::make_tuple(#name, "real"));
#define C_ENUM(name, type) config_fields.append(nb::make_tuple(#name, "enum"));
    OKID_AMBIENT_CONFIG_FIELDS(C_INT, C_REAL, C_ENUM)
#undef C_INT
#undef C_REAL
#undef C_ENUM
    m.attr("AMBIENT_CONFIG_FIELDS") = nb::tuple(config_fields);
    m.def(
        "ambient_identify",
        [](CBlock y, double dt, int hankel_rows, int order, std::vector<int> references, int sensing, int segments,
           int segment_samples, nb::object progress) -> nb::tuple {
            const size_t n = y.shape(0);
            const int mo = (int)y.shape(1);
            okid_ambient_config cfg;
            okid_config_issue issue{};
            /* L = 1: sizes only, to check the others first */
            int status = build_config(mo, dt, hankel_rows > 0 ? hankel_rows : 1, order, references, sensing, segments,
                                      segment_samples, &cfg, &issue);
            std::vector<okid_real> data;
            double band_hz = 0;
            auto_band band{};
            const auto_band *have_band = nullptr;
            /* with L and the order given nothing needs the whole mean-removed record: the means, then
               the record streamed through a small buffer (the same values as the copy, no copy) */
            const bool stream = hankel_rows > 0 && order > 0;
            okid_real mean[OKID_MAX_DIMENSION] = {0};
            if (status == OKID_OK && stream) {
                ambient_channel_means(y.data(), n, mo, mean);
                cfg.hankel_rows = hankel_rows;
                status = okid_ambient_config_check(&cfg, &issue);
            } else if (status == OKID_OK) {
                data.assign(y.data(), y.data() + n * (size_t)mo);
                ambient_remove_mean(data.data(), n, mo);
                const int refs = cfg.num_references > 0 ? cfg.num_references : mo;
                if (hankel_rows == 0) { /* the band once: for L here and for the physical modes' choice */
                    (void)ambient_record_band(data.data(), n, mo, dt, &band);
                    have_band = &band;
                    band_hz = band.low_hz;
                }
                cfg.hankel_rows = hankel_rows > 0 ? hankel_rows : ambient_band_hankel_rows(&band, n, mo, dt, order, refs);
                status = okid_ambient_config_check(&cfg, &issue);
            }
            if (status != OKID_OK) return refusal(status, issue, nb::none());
            /* without an order, the physical modes over three Hankel sizes (host_tools/common/ambient_modes.h) */
            std::unique_ptr<ambient_modes, ModesFree> am;
            if (order == 0) {
                am.reset(static_cast<ambient_modes *>(std::calloc(1, sizeof(ambient_modes))));
                if (!am) throw std::bad_alloc();
                {
                    nb::gil_scoped_release release;
                    status = ambient_modes_find(&cfg, hankel_rows > 0, have_band, n, data.data(), nullptr, am.get());
                }
                if (status != OKID_OK) {
                    return nb::make_tuple(status, std::string(), 0.0, 0.0, 0.0, nb::none());
                }
                cfg.order = am->order;
                cfg.hankel_rows = am->choice.windows[0];
                if (hankel_rows == 0) band_hz = am->choice.band_low_hz;
            }
            size_t bytes = 0;
            okid_ambient_workspace_size(&cfg, &bytes);
            std::unique_ptr<void, AlignedFree> ws(std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16));
            if (!ws) throw std::bad_alloc();
            okid_ambient amb;
            status = okid_ambient_init(&amb, &cfg, ws.get(), bytes, nullptr);
            const double work = work_per_sample(cfg);
            if (status == OKID_OK && stream) {
                const size_t rows = n < 4096 ? (n > 0 ? n : 1) : 4096; /* 16 batches of push_block */
                std::vector<okid_real> buffer(rows * (size_t)mo);
                status = feed_in_chunks(n, chunk_rows(work), progress, 0, n, [&](size_t first, size_t count) {
                    int st = OKID_OK;
                    for (size_t done = 0; done < count; done += rows) {
                        const size_t take = std::min(rows, count - done);
                        const double *src = y.data() + (first + done) * (size_t)mo;
                        for (size_t t = 0; t < take; ++t)
                            for (int a = 0; a < mo; ++a)
                                buffer[t * (size_t)mo + (size_t)a] = src[t * (size_t)mo + (size_t)a] - mean[a];
                        const int s = (int)okid_ambient_push_block(&amb, take, buffer.data(), (size_t)mo, nullptr);
                        if (s != OKID_OK) st = s;
                    }
                    return st;
                });
            } else if (status == OKID_OK) {
                status = feed_in_chunks(n, chunk_rows(work), progress, 0, n, [&](size_t first, size_t count) {
                    return (int)okid_ambient_push_block(&amb, count, data.data() + first * (size_t)mo, (size_t)mo,
                                                        nullptr);
                });
            }
            const int push_status = status;
            okid_ambient_result res{};
            if (status == OKID_OK || status == OKID_E_NONFINITE_SAMPLE) {
                nb::gil_scoped_release release;
                status = okid_ambient_identify(&amb, &res);
            }
            if (status != OKID_OK) {
                return nb::make_tuple(status, std::string(), 0.0, 0.0, 0.0, nb::none());
            }
            nb::dict d = result_dict(res, mo, cfg.hankel_rows, band_hz);
            d["rejected_samples"] = push_status == OKID_E_NONFINITE_SAMPLE;
            d["auto_json"] = nb::none();
            if (am) modes_into(d, *am, res, mo);
            return nb::make_tuple((int)OKID_OK, std::string(), 0.0, 0.0, 0.0, d);
        },
        nb::arg("y"), nb::arg("dt"), nb::arg("hankel_rows"), nb::arg("order"), nb::arg("references"),
        nb::arg("sensing"), nb::arg("segments"), nb::arg("segment_samples"), nb::arg("progress") = nb::none(),
        "Output-only identification of y (N, m): (status, field, value, min, max, result dict or None); "
        "field names the setting okid_ambient_config_check() refused.");
    nb::class_<AmbientCore>(m, "AmbientCore")
        .def(nb::init<>())
        .def(
            "init",
            [](AmbientCore &self, int num_outputs, double dt, int hankel_rows, int order, std::vector<int> references,
               int sensing, int segments, int segment_samples) {
                okid_config_issue issue{};
                okid_ambient_config cfg;
                int st = build_config(num_outputs, dt, hankel_rows, order, references, sensing, segments,
                                      segment_samples, &cfg, &issue);
                if (st != OKID_OK) return refusal(st, issue, nb::none());
                size_t bytes = 0;
                okid_ambient_workspace_size(&cfg, &bytes);
                std::unique_ptr<void, AlignedFree> ws(std::aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16));
                if (!ws) throw std::bad_alloc();
                st = okid_ambient_init(&self.amb, &cfg, ws.get(), bytes, nullptr);
                if (st == OKID_OK) {
                    self.cfg = cfg;
                    self.workspace = std::move(ws);
                    self.bytes = bytes;
                }
                return refusal(st, issue, nb::none());
            },
            "okid_ambient_init over a new workspace: (status, field, value, min, max, None).")
        .def_prop_ro("workspace_bytes", [](const AmbientCore &self) { return self.bytes; })
        .def(
            "push_block",
            [](AmbientCore &self, CBlock y, nb::object progress) {
                UseGuard guard(self.busy);
                if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, (size_t)0);
                const size_t mo = y.shape(1);
                size_t accepted = 0;
                // in chunks: Ctrl-C raises between two (the samples pushed so far stay pushed)
                const int s = feed_in_chunks(y.shape(0), chunk_rows(work_per_sample(self.cfg)), progress, 0,
                                             y.shape(0), [&](size_t first, size_t count) {
                    size_t taken = 0;
                    const int st = okid_ambient_push_block(&self.amb, count, y.data() + first * mo, mo, &taken);
                    accepted += taken;
                    return st;
                });
                return nb::make_tuple(s, accepted);
            },
            nb::arg("y"), nb::arg("progress").none() = nb::none(),
            "okid_ambient_push_block on a (count, m) C-contiguous block, no copy, in chunks: (status, accepted).")
        .def("identify",
             [](AmbientCore &self) {
                 UseGuard guard(self.busy);
                 if (!guard.acquired()) return nb::make_tuple(STATUS_BUSY, nb::none());
                 okid_ambient_result res{};
                 int st;
                 // order 0: the physical modes of the one Hankel size, then the model at the lowest
                 // order that holds them, from the same sums (ambient_modes_of); else the given order
                 std::unique_ptr<ambient_modes, ModesFree> am;
                 {
                     nb::gil_scoped_release release;
                     if (self.cfg.order == 0) {
                         am.reset(static_cast<ambient_modes *>(std::calloc(1, sizeof(ambient_modes))));
                         if (!am) throw std::bad_alloc();
                         st = ambient_modes_of(&self.amb, &self.cfg, am.get());
                         if (st == OKID_OK) {
                             st = am->order > 0 ? okid_ambient_identify_order(&self.amb, am->order, &res)
                                                : okid_ambient_identify(&self.amb, &res);
                         }
                     } else {
                         st = okid_ambient_identify(&self.amb, &res);
                     }
                 }
                 if (st != OKID_OK) return nb::make_tuple(st, nb::none());
                 const int mo = self.cfg.num_outputs;
                 nb::dict d = result_dict(res, mo, self.cfg.hankel_rows, 0.0);
                 d["auto_json"] = nb::none();
                 if (am) modes_into(d, *am, res, mo);
                 return nb::make_tuple(st, d);
             },
             "okid_ambient_identify of the sums so far: (status, result dict or None); with order 0 the physical "
             "modes of the one Hankel size and the model at the lowest order that holds them.")
        .def("reset", [](AmbientCore &self) {
            UseGuard guard(self.busy);
            return guard.acquired() ? (int)okid_ambient_reset(&self.amb) : STATUS_BUSY;
        });
}

}  // namespace okid_py
