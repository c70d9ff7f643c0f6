/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Loads the production FMI 2 FMUs (plant and identifier shared objects) with dlopen, couples them
 * for the paper's experiment and checks the identified frequencies and damping ratios against the
 * numpy reference. A C importer with no Python in between, so valgrind can check the FMUs.
 * Value references and tokens are read from the modelDescription.xml files next to them. Built
 * for the host and cross-built for the other platforms (run under Wine and qemu-user), it prints
 * the identified values with 17 digits so that the platforms can be compared.
 *   fmu_cosim PLANT_DIR IDENTIFIER_DIR [PLATFORM [select]]  (unpacked FMU folders of build/fmu/fmi2/;
 *                                                   PLATFORM linux64 (default), win64, aarch64-linux)
 * `select` leaves the order at 0, so that the identifier publishes its physical modes (the
 * stabilization table and the selection in their own memory: scripts/valgrind.sh checks that
 * path): on this noise-free record the Hankel matrix has rank 4, so the table ends at the exact
 * order-4 model whose poles count as confirmed (docs/quality.md section 8, "Noise-free data"): it
 * checks num_modes 2, no OKID_W_NO_PHYSICAL_MODE bit, and the exact modes as without it.
 */
#if !defined(_WIN32)
#define _XOPEN_SOURCE 700 /* realpath */
#endif
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_loader.h"
#include "okid/random.h"
#include "okid/status.h" /* OKID_W_NO_PHYSICAL_MODE */
#include "reference/reference_data.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)status;
    fprintf(stderr, "[%s %s] %s\n", name, category, message); /* okid's FMI 2 messages take no arguments */
}

static char *read_text(const char *dir, const char *file)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "fmu_cosim: cannot open %s\n", path);
        exit(2);
    }
    static char text[1 << 17];
    const size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    char *copy = malloc(n + 1);
    if (copy == NULL) exit(2);
    memcpy(copy, text, n + 1);
    return copy;
}

/* The value of attribute `attr` in the element that has name="name" (or the first one, name NULL). */
static const char *attribute(const char *xml, const char *name, const char *attr, char *out, size_t size)
{
    char key[128];
    const char *at = xml;
    if (name != NULL) {
        snprintf(key, sizeof key, "name=\"%s\"", name);
        at = strstr(xml, key);
    }
    snprintf(key, sizeof key, "%s=\"", attr);
    const char *v = at ? strstr(at, key) : NULL;
    if (v == NULL) {
        fprintf(stderr, "fmu_cosim: no %s for %s\n", attr, name ? name : "the model");
        exit(2);
    }
    v += strlen(key);
    const size_t len = (size_t)(strchr(v, '"') - v);
    snprintf(out, size, "%.*s", (int)len, v);
    return out;
}

static fmi2ValueReference vr_of(const char *xml, const char *name)
{
    char value[32];
    return (fmi2ValueReference)strtoul(attribute(xml, name, "valueReference", value, sizeof value), NULL, 10);
}

/* Instantiates and initialises with n integer parameters and the Boolean parameter `flag` (if any) set to true. */
static fmi2Component start(const fmi2_api *f, const char *name, const char *token, const char *dir,
                           const fmi2CallbackFunctions *cb, const fmi2ValueReference *vr, const fmi2Integer *iv,
                           size_t n, const fmi2ValueReference *flag)
{
    const fmi2Boolean yes = fmi2True;
    /* The resource location as a file: URI (an FMU written by okid-fmu keeps its configuration there). */
    char location[PATH_MAX + 32] = "";
#if !defined(_WIN32)
    char absolute[PATH_MAX];
    if (realpath(dir, absolute) != NULL) snprintf(location, sizeof location, "file://%s/resources", absolute);
#else
    (void)dir;
#endif
    fmi2Component c = f->instantiate(name, fmi2CoSimulation, token, location[0] ? location : NULL, cb, fmi2False,
                                     fmi2True);
    if (c == NULL || f->setup(c, fmi2False, 0, 0, fmi2False, 0) != fmi2OK || f->enter_init(c) != fmi2OK ||
        (n > 0 && f->set_integer(c, vr, n, iv) != fmi2OK) || (flag && f->set_boolean(c, flag, 1, &yes) != fmi2OK) ||
        f->exit_init(c) != fmi2OK) {
        fprintf(stderr, "fmu_cosim: cannot start %s\n", name);
        exit(1);
    }
    return c;
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 5 || (argc == 5 && strcmp(argv[4], "select") != 0)) {
        fprintf(stderr, "usage: fmu_cosim PLANT_DIR IDENTIFIER_DIR [PLATFORM [select]]\n");
        return 2;
    }
    const char *platform = argc >= 4 ? argv[3] : "linux64";
    const int select = argc == 5;
    const char *suffix = strcmp(platform, "win64") == 0 ? "dll" : "so";
    char *plant_xml = read_text(argv[1], "modelDescription.xml"), *ident_xml = read_text(argv[2], "modelDescription.xml");
    char path[1024], plant_token[128], ident_token[128], id[128];
    fmi2_api plant_api, ident_api;
    snprintf(path, sizeof path, "%s/binaries/%s/%s.%s", argv[1], platform,
             attribute(plant_xml, NULL, "modelIdentifier", id, sizeof id), suffix);
    fmi2_load(path, &plant_api);
    snprintf(path, sizeof path, "%s/binaries/%s/%s.%s", argv[2], platform,
             attribute(ident_xml, NULL, "modelIdentifier", id, sizeof id), suffix);
    fmi2_load(path, &ident_api);
    attribute(plant_xml, NULL, "guid", plant_token, sizeof plant_token);
    attribute(ident_xml, NULL, "guid", ident_token, sizeof ident_token);

    const fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    /* The paper's settings (p = 20, n = 4, 20 x 20 Hankel blocks, from rest); one identification, after the last sample */
    const fmi2ValueReference settings[5] = {vr_of(ident_xml, "observer_order"), vr_of(ident_xml, "order"),
                                            vr_of(ident_xml, "hankel_rows"), vr_of(ident_xml, "hankel_cols"),
                                            vr_of(ident_xml, "identify_every")};
    const fmi2Integer values[5] = {20, select ? 0 : 4, 20, 20, 1001};
    const fmi2ValueReference at_rest = vr_of(ident_xml, "zero_initial_state");
    const fmi2ValueReference ident_inputs[3] = {vr_of(ident_xml, "u1"), vr_of(ident_xml, "y1"), vr_of(ident_xml, "y2")};
    fmi2Component plant = start(&plant_api, "plant", plant_token, argv[1], &cb, NULL, NULL, 0, NULL);
    fmi2Component ident = start(&ident_api, "identifier", ident_token, argv[2], &cb, settings, values, 5, &at_rest);
    const fmi2ValueReference force_vr = vr_of(plant_xml, "force");
    const fmi2ValueReference acc_vr[2] = {vr_of(plant_xml, "acc1"), vr_of(plant_xml, "acc2")};
    okid_rng rng;
    okid_rng_seed(&rng, 11);
    for (int k = 0; k < 1001; ++k) {
        const double t = k * 0.01;
        double u, io[3];
        okid_rng_normal(&rng, 1, 1, &u, 1);
        plant_api.set_real(plant, &force_vr, 1, &u);
        plant_api.get_real(plant, acc_vr, 2, io + 1);
        io[0] = u;
        if (ident_api.set_real(ident, ident_inputs, 3, io) != fmi2OK || plant_api.do_step(plant, t, 0.01, fmi2True) != fmi2OK ||
            ident_api.do_step(ident, t, 0.01, fmi2True) > fmi2Warning) {
            fprintf(stderr, "fmu_cosim: step %d failed\n", k);
            return 1;
        }
    }
    const fmi2ValueReference modes[4] = {vr_of(ident_xml, "mode1_frequency_hz"), vr_of(ident_xml, "mode2_frequency_hz"),
                                         vr_of(ident_xml, "mode1_damping_ratio"), vr_of(ident_xml, "mode2_damping_ratio")};
    double got[4];
    ident_api.get_real(ident, modes, 4, got);
    const double want[4] = {PAPER_FREQ_HZ[0], PAPER_FREQ_HZ[1], PAPER_DAMPING_RATIO[0], PAPER_DAMPING_RATIO[1]};
    int bad = 0;
    if (select) {
        const fmi2ValueReference counts[2] = {vr_of(ident_xml, "num_modes"), vr_of(ident_xml, "warnings")};
        fmi2Integer count[2] = {-1, 0};
        ident_api.get_integer(ident, counts, 2, count);
        printf("selection: num_modes %d, warnings %d\n", (int)count[0], (int)count[1]);
        bad = count[0] != 2 || (count[1] & OKID_W_NO_PHYSICAL_MODE) != 0;
    }
    for (int i = 0; i < 4; ++i) {
        const double err = fabs(got[i] - want[i]) / want[i];
        printf("%s %d: identified %.17g exact %.17g relative error %.1e\n", i < 2 ? "frequency" : "damping", i % 2 + 1,
               got[i], want[i], err);
        bad |= !(err < 1e-9);
    }
    plant_api.terminate(plant);
    ident_api.terminate(ident);
    plant_api.free_instance(plant);
    ident_api.free_instance(ident);
    free(plant_xml);
    free(ident_xml);
    return bad;
}
