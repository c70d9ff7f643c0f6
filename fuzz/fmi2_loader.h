/* SPDX-License-Identifier: Apache-2.0 */
/* Loading an FMI 2 shared object (dlopen, or LoadLibrary on Windows): the entry points the fuzzer and the tests call. */
#ifndef OKID_FMI2_LOADER_H
#define OKID_FMI2_LOADER_H

#if defined(_WIN32)
#include <windows.h>
#else
#include <dlfcn.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

typedef struct fmi2_api {
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2DoStepTYPE *do_step;
    fmi2SetRealTYPE *set_real;
    fmi2GetRealTYPE *get_real;
    fmi2SetIntegerTYPE *set_integer;
    fmi2SetBooleanTYPE *set_boolean;
    fmi2GetIntegerTYPE *get_integer;
    fmi2ResetTYPE *reset;
    fmi2TerminateTYPE *terminate;
    fmi2SetDebugLoggingTYPE *set_debug_logging;
} fmi2_api;

static inline void *symbol(void *lib, const char *name)
{
#if defined(_WIN32)
    void *f = NULL;
    FARPROC proc = GetProcAddress((HMODULE)lib, name);
    memcpy(&f, &proc, sizeof f);
#else
    void *f = dlsym(lib, name);
#endif
    if (f == NULL) {
        fprintf(stderr, "the FMU does not export %s\n", name);
        abort();
    }
    return f;
}

/* Loads path and resolves every entry point (aborts when one is missing). */
static inline void fmi2_load(const char *path, fmi2_api *a)
{
#if defined(_WIN32)
    void *lib = (void *)LoadLibraryA(path);
    if (lib == NULL) {
        fprintf(stderr, "LoadLibrary %s: error %lu\n", path, (unsigned long)GetLastError());
        abort();
    }
#else
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        abort();
    }
#endif
    /* POSIX lets a dlsym result become a function pointer; ISO C needs the bytes copied. */
#define OKID_FMI2_RESOLVE(field, name)              \
    do {                                             \
        void *p_ = symbol(lib, name);                \
        memcpy(&a->field, &p_, sizeof a->field);     \
    } while (0)
    OKID_FMI2_RESOLVE(instantiate, "fmi2Instantiate");
    OKID_FMI2_RESOLVE(free_instance, "fmi2FreeInstance");
    OKID_FMI2_RESOLVE(setup, "fmi2SetupExperiment");
    OKID_FMI2_RESOLVE(enter_init, "fmi2EnterInitializationMode");
    OKID_FMI2_RESOLVE(exit_init, "fmi2ExitInitializationMode");
    OKID_FMI2_RESOLVE(do_step, "fmi2DoStep");
    OKID_FMI2_RESOLVE(set_real, "fmi2SetReal");
    OKID_FMI2_RESOLVE(get_real, "fmi2GetReal");
    OKID_FMI2_RESOLVE(set_integer, "fmi2SetInteger");
    OKID_FMI2_RESOLVE(set_boolean, "fmi2SetBoolean");
    OKID_FMI2_RESOLVE(get_integer, "fmi2GetInteger");
    OKID_FMI2_RESOLVE(reset, "fmi2Reset");
    OKID_FMI2_RESOLVE(terminate, "fmi2Terminate");
    OKID_FMI2_RESOLVE(set_debug_logging, "fmi2SetDebugLogging");
#undef OKID_FMI2_RESOLVE
}

#endif
