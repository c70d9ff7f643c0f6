// SPDX-License-Identifier: Apache-2.0
// The host library's rules for Python (host_tools/common): the explanation of a refused
// configuration and the CLI's record reader, so that okid and okid.fleet keep no copy of them.
#include <cstdio>  // before nanobind (binding.h says why)

#include <optional>
#include <string>

#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include "binding.h"

extern "C" {
#include "config_explain.h"
#include "record_load.h"
#include "time_column.h"
}

namespace okid_py {

namespace {
// record_data_free however the conversion ends (an allocation that throws included).
struct LoadedRecord {
    record_data data{};
    ~LoadedRecord() { record_data_free(&data); }
};
}  // namespace

void bind_host(nb::module_ &m)
{
    m.def(
        "explain_config",
        [](const nb::dict &d) {
            const okid_config cfg = config_from_dict(d);
            size_t bytes = 0;
            const int status = okid_workspace_size(&cfg, &bytes);
            char message[640] = "";
            const char *field = nullptr;
            if (status != OKID_OK) field = config_explain(&cfg, (okid_status)status, CONFIG_EXPLAIN_PYTHON, message, sizeof message);
            return nb::make_tuple(status, field ? nb::object(nb::str(field)) : nb::none(), std::string(message));
        },
        "(status of okid_workspace_size, the field okid_config_check names or None, the one-line explanation).");
    m.def(
        "data_shortfall",
        [](const nb::dict &d, unsigned long long samples) -> std::optional<std::string> {
            const okid_config cfg = config_from_dict(d);
            char message[320];
            if (!config_data_shortfall(&cfg, samples, message, sizeof message)) return std::nullopt;
            return std::string(message);
        },
        "The refusal when samples cannot give the regressor rows cfg needs (the CLI's check), else None.");
    m.def("time_column_unit", [](const std::string &name) { return time_column_unit(name.c_str()); },
          "Seconds per unit of a time column named so (time_column.h), 0 when the name marks none.");
    m.def(
        "read_record",
        [](const std::string &path, std::optional<std::string> inputs, std::optional<std::string> outputs,
           std::optional<double> dt, bool ignore_time_column) {
            record_request request{inputs ? inputs->c_str() : nullptr, outputs ? outputs->c_str() : nullptr,
                                   dt.has_value(), dt.value_or(0.0), ignore_time_column};
            LoadedRecord loaded;
            record_data &data = loaded.data;
            char error[640] = "";
            int code;
            {
                nb::gil_scoped_release release;
                code = record_load(path.c_str(), &request, &data, error, sizeof error);
            }
            if (code != 0) return nb::make_tuple(code, std::string(error));
            std::vector<double> u(data.u, data.u + data.samples * (size_t)data.r);
            std::vector<double> y(data.y, data.y + data.samples * (size_t)data.m);
            nb::list inames, onames;
            for (int i = 0; i < data.r; ++i) inames.append(nb::str(data.input_names[i]));
            for (int a = 0; a < data.m; ++a) onames.append(nb::str(data.output_names[a]));
            nb::object start = data.has_time ? nb::object(nb::float_(data.first_stamp)) : nb::none();
            nb::tuple out = nb::make_tuple(0, std::string(), owned_array(std::move(u), {data.samples, (size_t)data.r}),
                                           owned_array(std::move(y), {data.samples, (size_t)data.m}), data.dt,
                                           nb::tuple(inames), nb::tuple(onames), start);
            return out;
        },
        nb::arg("path"), nb::arg("inputs").none(), nb::arg("outputs").none(), nb::arg("dt").none(),
        nb::arg("ignore_time_column"),
        "record_load: (0, '', u, y, dt, input_names, output_names, first stamp [s] or None), or (code, message).");
}

}  // namespace okid_py
