/* SPDX-License-Identifier: Apache-2.0 */
/* Links an installed okid: simulate the paper's 2-DOF case, identify it, check two modes come out. */
#include <stdio.h>
#include <stdlib.h>

#include <okid/okid.h>

enum { SAMPLES = 600 };

int main(void)
{
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    const okid_real b2[2] = {1, 0}, ca[4] = {1, 0, 0, 1};
    okid_real mm[4], rr[4], kk[4], ac[16], bc[4], a[16], b[4], c[8], d[2], x[4], tmp[4];
    static okid_real work[OKID_ZOH_WORK_REALS(4, 1)], u[SAMPLES], y[2 * SAMPLES];
    okid_chain_model(2, masses, dampers, springs, mm, rr, kk);
    const okid_mechanical_model model = {2, 1, 2, mm, rr, kk, b2, ca, NULL, NULL};
    okid_model_state_space(&model, ac, bc, c, d, work, OKID_STATE_SPACE_WORK_REALS(2, 1));
    okid_discretize_zoh(4, 1, ac, bc, 0.01, a, b, work, OKID_ZOH_WORK_REALS(4, 1));
    okid_rng rng;
    okid_rng_seed(&rng, 1);
    okid_rng_normal(&rng, 1, SAMPLES, u, 1);
    okid_simulator sim;
    okid_simulator_init(&sim, 4, 1, 2, a, b, c, d, x, tmp);
    okid_simulate(&sim, SAMPLES, u, 1, y, 2);

    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = 0.01;
    cfg.observer_order = 10;
    cfg.order = 4;
    cfg.zero_initial_state = 1;
    size_t bytes = 0;
    if (okid_workspace_size(&cfg, &bytes) != OKID_OK) {
        return 1;
    }
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    okid_identifier id;
    okid_result res;
    okid_status st = okid_init(&id, &cfg, ws, bytes, NULL);
    if (st == OKID_OK) {
        st = okid_push_block(&id, SAMPLES, u, 1, y, 2, NULL);
    }
    if (st == OKID_OK) {
        st = okid_identify(&id, &res);
    }
    if (st != OKID_OK || res.num_modes != 2) {
        fprintf(stderr, "consumer: %s\n", okid_status_str(st));
        free(ws);
        return 1;
    }
    printf("consumer: okid %s identified %.6f Hz and %.6f Hz\n", OKID_VERSION_STRING,
           (double)res.modes[0].frequency_hz, (double)res.modes[1].frequency_hz);
    free(ws);
    return 0;
}
