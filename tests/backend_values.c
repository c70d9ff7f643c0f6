/* SPDX-License-Identifier: Apache-2.0 */
/* The modal parameters of the reference cases, flattened for the backend comparison. */
#include "backend_values.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_support.h"

static void add(backend_value *values, int max, int *count, const char *what, int mode, int index, double value,
                double scale, double tol)
{
    assert_true(*count < max);
    backend_value *v = &values[(*count)++];
    snprintf(v->name, sizeof v->name, "%s.%d.%d", what, mode, index);
    v->value = value;
    v->scale = scale;
    v->tol = tol;
}

int backend_case_values(backend_value *values, int max)
{
    /* case, samples and seed as in test_identify_accuracy */
    const struct {
        const ref_case *rc;
        size_t samples;
        uint64_t seed;
    } runs[] = {{&REF_PAPER, 1000, 2024}, {&REF_MIMO, 1500, 11}, {&REF_CHAIN3, 2000, 5}};
    int count = 0;
    for (size_t c = 0; c < sizeof runs / sizeof runs[0]; ++c) {
        const ref_case *rc = runs[c].rc;
        okid_config cfg;
        test_config(rc, &cfg);
        okid_identifier id;
        okid_result res;
        void *ws = NULL;
        assert_int_equal(test_identify_case(rc, &cfg, runs[c].samples, runs[c].seed, &id, &ws, &res), OKID_OK);
        add(values, max, &count, rc->name, 0, 0, res.num_modes, 1, 0);
        for (int i = 0; i < res.num_modes; ++i) {
            const okid_mode *md = &res.modes[i];
            const double lambda = hypot(md->eigenvalue.re, md->eigenvalue.im);
            const double tol = TOL(1e-9, 2 * identify_tol(rc));
#if OKID_REAL_IS_FLOAT /* the magnifications of assert_modes_match: s = ln(lambda) / dt, zeta = -Re s / |s| */
            const double s_tol = tol / (hypot(md->pole.re, md->pole.im) * rc->dt);
            const double zeta_tol = 2 * s_tol / md->damping_ratio;
#else
            const double s_tol = tol, zeta_tol = tol;
#endif
            add(values, max, &count, "eigenvalue_re", i, (int)c, md->eigenvalue.re, lambda, tol);
            add(values, max, &count, "eigenvalue_im", i, (int)c, md->eigenvalue.im, lambda, tol);
            add(values, max, &count, "frequency_hz", i, (int)c, md->frequency_hz, fabs(md->frequency_hz), s_tol);
            add(values, max, &count, "damping_ratio", i, (int)c, md->damping_ratio, fabs(md->damping_ratio), zeta_tol);
            for (int a = 0; a < rc->m; ++a) { /* unit norm, largest component real: relative to 1 */
                add(values, max, &count, "sensor_shape_re", i, a, md->sensor_shape[a].re, 1, s_tol);
                add(values, max, &count, "sensor_shape_im", i, a, md->sensor_shape[a].im, 1, s_tol);
            }
            add(values, max, &count, "emac", i, (int)c, md->emac, 1, s_tol); /* indicators lie in [0, 1] */
            add(values, max, &count, "mpc", i, (int)c, md->mpc, 1, s_tol);
            add(values, max, &count, "msv", i, (int)c, md->msv, fabs(md->msv), s_tol);
        }
        free(ws);
    }
    return count;
}
