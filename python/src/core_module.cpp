// SPDX-License-Identifier: Apache-2.0
// okid._core: the C library in-process. The Python layer (okid/__init__.py and friends) gives it
// keywords, validation messages and exceptions; this module only calls the C API.
#include "binding.h"

#include <nanobind/stl/string.h>

namespace okid_py {

NB_MODULE(_core, m)
{
    m.doc() = "okid's C core (internal: use the okid package).";
    m.attr("MAX_DIMENSION") = OKID_MAX_DIMENSION;
    m.attr("MAX_HORIZON") = OKID_MAX_HORIZON;
    m.attr("MAX_ORDER") = OKID_MAX_ORDER;
    m.attr("MAX_DECIMATION") = OKID_MAX_DECIMATION;
    m.attr("MAX_INSTRUMENT_LAGS") = OKID_MAX_INSTRUMENT_LAGS;
    m.attr("STATUS_BUSY") = STATUS_BUSY;
    m.attr("VERSION") = OKID_VERSION_STRING;
    m.def("status_str", [](int status) { return std::string(okid_status_str((okid_status)status)); });
    m.def("warning_str", [](unsigned bit) { return std::string(okid_warning_str(bit)); });
    bind_identifier(m);
    bind_model(m);
    bind_refine(m);
    bind_host(m);
    bind_auto(m);
    bind_ambient(m);
}

}  // namespace okid_py
