/* SPDX-License-Identifier: Apache-2.0 */
/*
 * A C importer of the FMI 3 identifier FMU with its structural parameters, for every platform
 * (host, and cross-built for win64 and aarch64-linux, run under Wine and qemu-user): configuration
 * mode with num_inputs 2, num_outputs 3, max_modes 3; the 3-DOF chain of
 * tests/python/test_fmu.py (forces on masses 1 and 3, accelerations of all three, simulated here
 * with okid's exact zero-order hold); prints the identified modes with 17 digits, which
 * tests/python/test_fmu_platforms.py compares with numpy's exact modes and across the platforms.
 * It runs the case twice, with fmi3Reset and a new configuration in between, and requires the same
 * bits both times (valgrind checks the allocations of both configurations). A third run after one
 * more fmi3Reset configures num_inputs 0 (output-only identification: the correlation sums, the
 * stabilization table and the selection in their own memory) and feeds the accelerations alone;
 * it requires one identification (its modes are estimates from correlations: test_fmu.py checks
 * those against the CLI).
 *   fmu3_chain IDENTIFIER_DIR [PLATFORM]   (unpacked FMU of build/fmu/fmi3; x86_64-linux by default)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
#include <windows.h>
#else
#include <dlfcn.h>
#endif

#include "fmi3Functions.h"
#include "okid/okid.h"
#include "okid/random.h"

enum { DOFS = 3, R = 2, M = 3, STATES = 2 * DOFS, SAMPLES = 1001 };

static void *library;
/* The FMU's entry points. */
static fmi3InstantiateCoSimulationTYPE *instantiate;
static fmi3EnterConfigurationModeTYPE *enter_configuration;
static fmi3ExitConfigurationModeTYPE *exit_configuration;
static fmi3SetUInt64TYPE *set_uint64;
static fmi3SetInt32TYPE *set_int32;
static fmi3SetFloat64TYPE *set_float64;
static fmi3SetBooleanTYPE *set_boolean;
static fmi3GetFloat64TYPE *get_float64;
static fmi3GetInt32TYPE *get_int32;
static fmi3EnterInitializationModeTYPE *enter_init;
static fmi3ExitInitializationModeTYPE *exit_init;
static fmi3DoStepTYPE *do_step;
static fmi3ResetTYPE *reset;
static fmi3TerminateTYPE *terminate;
static fmi3FreeInstanceTYPE *free_instance;
static const double DT = 0.01;


static void *symbol(const char *name)
{
#if defined(_WIN32)
    FARPROC proc = GetProcAddress((HMODULE)library, name);
    void *f;
    memcpy(&f, &proc, sizeof f);
#else
    void *f = dlsym(library, name);
#endif
    if (f == NULL) {
        fprintf(stderr, "fmu3_chain: the FMU does not export %s\n", name);
        exit(2);
    }
    return f;
}

/* ISO C: a data pointer's bytes copied into a function pointer. */
#define RESOLVE(var, name) memcpy(&(var), &(void *){symbol(name)}, sizeof(var))

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "fmu3_chain: cannot open %s\n", path);
        exit(2);
    }
    fseek(f, 0, SEEK_END);
    const long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)size + 1);
    if (text == NULL || fread(text, 1, (size_t)size, f) != (size_t)size) exit(2);
    text[size] = '\0';
    fclose(f);
    return text;
}

/* The value of attribute attr of the element with name="name" (the first element when name is NULL). */
static void attribute(const char *xml, const char *name, const char *attr, char *out, size_t size)
{
    char key[128];
    const char *at = xml;
    if (name) {
        snprintf(key, sizeof key, "name=\"%s\"", name);
        at = strstr(xml, key);
    }
    snprintf(key, sizeof key, " %s=\"", attr);
    const char *v = at ? strstr(at, key) : NULL;
    if (v == NULL) {
        fprintf(stderr, "fmu3_chain: no %s for %s\n", attr, name ? name : "the model");
        exit(2);
    }
    v += strlen(key);
    snprintf(out, size, "%.*s", (int)(strchr(v, '"') - v), v);
}

static fmi3ValueReference vr(const char *xml, const char *name)
{
    char text[32];
    attribute(xml, name, "valueReference", text, sizeof text);
    return (fmi3ValueReference)strtoul(text, NULL, 10);
}

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message)
{
    (void)env, (void)status;
    fprintf(stderr, "[%s] %s\n", category, message);
}

static void check(fmi3Status status, const char *what)
{
    if (status != fmi3OK) {
        fprintf(stderr, "fmu3_chain: %s returned %d\n", what, (int)status);
        exit(1);
    }
}

/* The chain's exact ZOH model at dt and its response to white-noise forces (R x SAMPLES, M x SAMPLES). */
static void simulate(double dt, double *u, double *y)
{
    const okid_real masses[DOFS] = {2.0, 3.0, 2.5}, dampers[DOFS + 1] = {2.0, 4.0, 3.0, 2.0},
                    springs[DOFS + 1] = {20.0, 40.0, 30.0, 25.0};
    okid_real mm[DOFS * DOFS], rr[DOFS * DOFS], kk[DOFS * DOFS], b2[DOFS * R] = {0}, ca[M * DOFS] = {0};
    b2[0] = 1;            /* force 1 on mass 1 */
    b2[DOFS + 2] = 1;     /* force 2 on mass 3 */
    for (int i = 0; i < DOFS; ++i) ca[i + i * M] = 1;
    static okid_real ac[STATES * STATES], bc[STATES * R], c[M * STATES], d[M * R], a[STATES * STATES], b[STATES * R];
    static okid_real work[OKID_ZOH_WORK_REALS(STATES, R) + 64 * STATES * STATES], state[STATES], scratch[4 * STATES];
    const okid_mechanical_model model = {DOFS, R, M, mm, rr, kk, b2, ca, NULL, NULL};
    okid_simulator sim;
    okid_rng rng;
    const size_t nwork = sizeof work / sizeof work[0];
    if (okid_chain_model(DOFS, masses, dampers, springs, mm, rr, kk) != OKID_OK ||
        okid_model_state_space(&model, ac, bc, c, d, work, nwork) != OKID_OK ||
        okid_discretize_zoh(STATES, R, ac, bc, dt, a, b, work, nwork) != OKID_OK ||
        okid_simulator_init(&sim, STATES, R, M, a, b, c, d, state, scratch) != OKID_OK) {
        fprintf(stderr, "fmu3_chain: the chain model failed\n");
        exit(2);
    }
    okid_rng_seed(&rng, 7);
    okid_rng_normal(&rng, 1, (size_t)R * SAMPLES, u, 1);
    if (okid_simulate(&sim, SAMPLES, u, R, y, M) != OKID_OK) exit(2);
}

/* Configures (2 inputs, 3 outputs, 3 modes), initialises, feeds the chain and reads the modes (6 values). */
static int identify(fmi3Instance fmu, const char *xml, const double *u, const double *y, double *modes_out)
{
    const fmi3ValueReference sizes[3] = {vr(xml, "num_inputs"), vr(xml, "num_outputs"), vr(xml, "max_modes")};
    const fmi3UInt64 size_values[3] = {R, M, 3};
    check(enter_configuration(fmu), "fmi3EnterConfigurationMode");
    check(set_uint64(fmu, sizes, 3, size_values, 3), "fmi3SetUInt64");
    check(exit_configuration(fmu), "fmi3ExitConfigurationMode");
    const fmi3ValueReference settings[5] = {vr(xml, "observer_order"), vr(xml, "order"), vr(xml, "hankel_rows"),
                                            vr(xml, "hankel_cols"), vr(xml, "identify_every")};
    const fmi3Int32 values[5] = {10, 6, 20, 20, SAMPLES};
    const fmi3ValueReference at_rest = vr(xml, "zero_initial_state"), dt_vr = vr(xml, "dt");
    const fmi3Boolean yes = fmi3True;
    check(set_int32(fmu, settings, 5, values, 5), "fmi3SetInt32");
    check(set_boolean(fmu, &at_rest, 1, &yes, 1), "fmi3SetBoolean");
    check(set_float64(fmu, &dt_vr, 1, &DT, 1), "fmi3SetFloat64");
    check(enter_init(fmu, fmi3False, 0, 0, fmi3False, 0), "fmi3EnterInitializationMode");
    check(exit_init(fmu), "fmi3ExitInitializationMode");
    const fmi3ValueReference inputs[2] = {vr(xml, "u"), vr(xml, "y")};
    for (int k = 0; k < SAMPLES; ++k) {
        double io[R + M];
        memcpy(io, &u[k * R], sizeof(double) * R);
        memcpy(io + R, &y[k * M], sizeof(double) * M);
        fmi3Boolean event, stop, early;
        fmi3Float64 last;
        check(set_float64(fmu, inputs, 2, io, R + M), "fmi3SetFloat64 (u, y)");
        check(do_step(fmu, k * DT, DT, fmi3True, &event, &stop, &early, &last), "fmi3DoStep");
    }
    const fmi3ValueReference modes[2] = {vr(xml, "mode_frequency_hz"), vr(xml, "mode_damping_ratio")};
    const fmi3ValueReference count_vr = vr(xml, "identifications");
    fmi3Int32 identifications = 0;
    check(get_float64(fmu, modes, 2, modes_out, 6), "fmi3GetFloat64 (modes)");
    check(get_int32(fmu, &count_vr, 1, &identifications, 1), "fmi3GetInt32");
    return identifications == 1;
}

/*
 * num_inputs 0, num_outputs 3, Hankel size L, the order given (0: the physical modes): y alone; 1
 * when it identified once. L = 20 and order 40 are above what the Eigen platforms held with the
 * firmware's OKID_EIGEN_MAX_ORDER of 32 (refused there); the FMUs are built with 64.
 */
static int identify_output_only(fmi3Instance fmu, const char *xml, const double *y, int hankel_rows, int order)
{
    const fmi3ValueReference sizes[3] = {vr(xml, "num_inputs"), vr(xml, "num_outputs"), vr(xml, "max_modes")};
    const fmi3UInt64 size_values[3] = {0, M, 3};
    check(enter_configuration(fmu), "fmi3EnterConfigurationMode");
    check(set_uint64(fmu, sizes, 3, size_values, 3), "fmi3SetUInt64");
    check(exit_configuration(fmu), "fmi3ExitConfigurationMode");
    const fmi3ValueReference settings[3] = {vr(xml, "hankel_rows"), vr(xml, "identify_every"), vr(xml, "order")},
                             dt_vr = vr(xml, "dt");
    const fmi3Int32 values[3] = {hankel_rows, SAMPLES, order};
    check(set_int32(fmu, settings, 3, values, 3), "fmi3SetInt32");
    check(set_float64(fmu, &dt_vr, 1, &DT, 1), "fmi3SetFloat64");
    check(enter_init(fmu, fmi3False, 0, 0, fmi3False, 0), "fmi3EnterInitializationMode");
    check(exit_init(fmu), "fmi3ExitInitializationMode");
    const fmi3ValueReference outputs = vr(xml, "y");
    for (int k = 0; k < SAMPLES; ++k) {
        fmi3Boolean event, stop, early;
        fmi3Float64 last;
        check(set_float64(fmu, &outputs, 1, &y[k * M], M), "fmi3SetFloat64 (y)");
        check(do_step(fmu, k * DT, DT, fmi3True, &event, &stop, &early, &last), "fmi3DoStep");
    }
    const fmi3ValueReference count_vr = vr(xml, "identifications");
    fmi3Int32 identifications = 0;
    check(get_int32(fmu, &count_vr, 1, &identifications, 1), "fmi3GetInt32");
    return identifications == 1;
}

int main(int argc, char **argv)
{
    if (argc != 2 && argc != 3) {
        fprintf(stderr, "usage: fmu3_chain IDENTIFIER_DIR [PLATFORM]\n");
        return 2;
    }
    const char *platform = argc == 3 ? argv[2] : "x86_64-linux";
    char path[1024], token[256], id[128];
    snprintf(path, sizeof path, "%s/modelDescription.xml", argv[1]);
    char *xml = read_text(path);
    attribute(xml, NULL, "modelIdentifier", id, sizeof id);
    attribute(xml, NULL, "instantiationToken", token, sizeof token);
    snprintf(path, sizeof path, "%s/binaries/%s/%s.%s", argv[1], platform, id, strstr(platform, "windows") ? "dll" : "so");
#if defined(_WIN32)
    library = (void *)LoadLibraryA(path);
#else
    library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
#endif
    if (library == NULL) {
        fprintf(stderr, "fmu3_chain: cannot load %s\n", path);
        return 2;
    }
    RESOLVE(instantiate, "fmi3InstantiateCoSimulation");
    RESOLVE(enter_configuration, "fmi3EnterConfigurationMode");
    RESOLVE(exit_configuration, "fmi3ExitConfigurationMode");
    RESOLVE(set_uint64, "fmi3SetUInt64");
    RESOLVE(set_int32, "fmi3SetInt32");
    RESOLVE(set_float64, "fmi3SetFloat64");
    RESOLVE(set_boolean, "fmi3SetBoolean");
    RESOLVE(get_float64, "fmi3GetFloat64");
    RESOLVE(get_int32, "fmi3GetInt32");
    RESOLVE(enter_init, "fmi3EnterInitializationMode");
    RESOLVE(exit_init, "fmi3ExitInitializationMode");
    RESOLVE(do_step, "fmi3DoStep");
    RESOLVE(reset, "fmi3Reset");
    RESOLVE(terminate, "fmi3Terminate");
    RESOLVE(free_instance, "fmi3FreeInstance");

    static double u[R * SAMPLES], y[M * SAMPLES];
    simulate(DT, u, y);

    fmi3Instance fmu = instantiate("chain", token, NULL, fmi3False, fmi3True, fmi3False, fmi3False, NULL, 0, NULL,
                                   logger, NULL);
    if (fmu == NULL) return 1;
    double first[6], again[6];
    const int ok = identify(fmu, xml, u, y, first);
    check(reset(fmu), "fmi3Reset");
    const int ok_again = identify(fmu, xml, u, y, again);
    for (int k = 0; k < 3; ++k) printf("mode %d: frequency_hz %.17g damping_ratio %.17g\n", k + 1, first[k], first[3 + k]);
    if (memcmp(first, again, sizeof first) != 0) {
        fprintf(stderr, "fmu3_chain: the run after fmi3Reset differs\n");
        return 1;
    }
    check(reset(fmu), "fmi3Reset");
    if (!identify_output_only(fmu, xml, y, 10, 0)) {
        fprintf(stderr, "fmu3_chain: the output-only run did not identify\n");
        return 1;
    }
    check(reset(fmu), "fmi3Reset");
    if (!identify_output_only(fmu, xml, y, 20, 40)) {
        fprintf(stderr, "fmu3_chain: the output-only run at order 40 did not identify\n");
        return 1;
    }
    terminate(fmu);
    free_instance(fmu);
    free(xml);
    return ok && ok_again ? 0 : 1;
}
