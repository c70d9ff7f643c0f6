/* SPDX-License-Identifier: Apache-2.0 */
/*
 * libFuzzer target: the identifier FMU's FMI 2 entry points, through its shared object (built with
 * the sanitizers by fuzz/CMakeLists.txt and loaded with dlopen), driven by a byte stream: random
 * sequences of calls with random value references, values (NaN, Inf, huge), times and step sizes,
 * in every state. Invariants: no crash, no sanitizer report, every status a valid fmi2Status,
 * and a logger that receives printf-safe text.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi2_loader.h"
#include "fuzz_input.h"

static const fmi2_api *api(void)
{
    static fmi2_api a;
    static int loaded;
    if (!loaded) {
        fmi2_load(OKID_FUZZ_FMU_PATH, &a);
        loaded = 1;
    }
    return &a;
}

/* A printf-style importer: the message must be a safe format (okid doubles every '%'). */
static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)name, (void)status, (void)category;
    char out[2048];
    va_list args;
    va_start(args, message);
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wformat-nonliteral" /* on purpose: FMI 2 messages are formats */
    vsnprintf(out, sizeof out, message, args);
#pragma clang diagnostic pop
    va_end(args);
}

static void check(fmi2Status st)
{
    if ((int)st < fmi2OK || (int)st > fmi2Pending) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const fmi2_api *f = api();
    fuzz_input in = {data, size, 0};
    const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    const char *token = fuzz_byte(&in) < 16 ? "{wrong}" : OKID_FUZZ_FMU_TOKEN;
    fmi2Component c = f->instantiate(fuzz_byte(&in) < 8 ? "" : "fuzz%s%n", fmi2CoSimulation, token, NULL, &callbacks,
                                     fmi2False, fuzz_int(&in, 0, 1));
    if (c == NULL) return 0;
    double time = 0;
    for (int op = 0; op < 300 && in.pos < in.size; ++op) {
        fmi2ValueReference vr = (fmi2ValueReference)fuzz_int(&in, 0, 220);
        switch (fuzz_byte(&in) % 12) {
        case 0: {
            const fmi2Real v = fuzz_real(&in);
            check(f->set_real(c, &vr, 1, &v));
            break;
        }
        case 1: {
            const fmi2Integer v = fuzz_int(&in, -3, 80);
            check(f->set_integer(c, &vr, 1, &v));
            break;
        }
        case 2: {
            fmi2Real v;
            check(f->get_real(c, &vr, 1, &v));
            break;
        }
        case 3: {
            fmi2Integer v;
            check(f->get_integer(c, &vr, 1, &v));
            break;
        }
        case 4:
            check(f->setup(c, fmi2False, 0, fuzz_byte(&in) < 200 ? 0.0 : fuzz_real(&in), fmi2False, 0));
            break;
        case 5:
            check(f->enter_init(c));
            break;
        case 6:
            check(f->exit_init(c));
            break;
        case 7: case 8: case 9: { /* steps: mostly the right time and size, sometimes not */
            const double h = fuzz_byte(&in) < 230 ? 0.01 : fuzz_real(&in);
            const double t = fuzz_byte(&in) < 230 ? time : fuzz_real(&in);
            const fmi2ValueReference inputs[3] = {11, 12, 13};
            fmi2Real values[3];
            for (int i = 0; i < 3; ++i) values[i] = fuzz_byte(&in) < 250 ? ((double)fuzz_int(&in, 0, 2000) - 1000) / 300 : fuzz_real(&in);
            check(f->set_real(c, inputs, 3, values));
            const fmi2Status st = f->do_step(c, t, h, fmi2True);
            check(st);
            if (st <= fmi2Warning) time = t + h;
            break;
        }
        case 10:
            if (fuzz_byte(&in) < 40) {
                check(f->reset(c));
                time = 0;
            } else {
                check(f->terminate(c));
            }
            break;
        default: {
            const char *categories[2] = {"logEvents", fuzz_byte(&in) < 128 ? "logStatusError" : "log%s%n"};
            check(f->set_debug_logging(c, fuzz_int(&in, 0, 1), (size_t)fuzz_int(&in, 0, 2), categories));
            break;
        }
        }
    }
    f->free_instance(c);
    return 0;
}
