/* SPDX-License-Identifier: Apache-2.0 */
/* Stabilization diagram data (okid/stabilization.h): nested truncation against direct
   realizations, the true poles at every order, the rank limit, and the API contract. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { PAPER_SAMPLES = 1001, MAX_ORDER = 16 };

static void *stab_workspace(const okid_identifier *id, int max_order, int step, size_t *bytes)
{
    assert_int_equal(okid_stabilization_workspace_size(id, max_order, step, bytes), OKID_OK);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (*bytes + 15u) / 16u * 16u);
    assert_non_null(ws);
    return ws;
}

/* The table's mode nearest (in eigenvalue) to lambda among order o's modes: distance |lambda - mode| / |lambda|. */
static double nearest(const okid_stabilization *st, int o, double re, double im, const okid_mode **found)
{
    double best = INFINITY;
    const okid_stabilization_order *ord = &st->orders[o];
    for (int k = 0; k < ord->num_modes; ++k) {
        const okid_mode *md = &st->modes[ord->first + k];
        const double d = hypot(md->eigenvalue.re - re, md->eigenvalue.im - im) / hypot(re, im);
        if (d < best) {
            best = d;
            *found = md;
        }
    }
    return best;
}

/*
 * Low-noise data, p = 60 and a 100 x 100 Hankel (the 2 s span the CLI recommends): every order
 * from 4 to 16 holds both exact eigenvalues (numpy) to 0.2 times the noise level (measured: 0.03
 * times, in both precisions), marked stable from order 6 on, with CMI near 1. The orders above 4
 * exist only where noise lifts the Hankel's singular values above its round-off floor
 * eps k sigma_1 (rank_limit): 1e-8 noise does in double, but is below float's round-off (the table
 * would stop at order 4, as in test_rank_limit), so float takes 1e-4.
 */
static void test_true_poles_at_every_order(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.observer_order = 60;
    cfg.hankel_rows = cfg.hankel_cols = 100;
    const double noise = TOL(1e-8, 1e-4);
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(test_identify_noisy(&REF_PAPER, &cfg, PAPER_SAMPLES, 3, noise, &id, &ws, &res), OKID_OK);
    size_t bytes = 0;
    void *sws = stab_workspace(&id, MAX_ORDER, 2, &bytes);
    okid_stabilization st;
    assert_int_equal(okid_stabilization_compute(&id, MAX_ORDER, 2, NULL, sws, bytes, &st), OKID_OK);
    assert_int_equal(st.num_orders, MAX_ORDER / 2);
    for (int o = 0; o < st.num_orders; ++o) {
        assert_int_equal(st.orders[o].order, 2 * (o + 1));
        assert_true(st.orders[o].num_modes >= 1 && st.orders[o].num_modes <= st.orders[o].order);
        if (st.orders[o].order < 4) continue;
        for (int i = 0; i < REF_PAPER.num_modes; ++i) {
            const okid_mode *md = NULL;
            const double err = nearest(&st, o, REF_PAPER.eig_re[i], fabs(REF_PAPER.eig_im[i]), &md);
            check_within_at(__FILE__, __LINE__, "eigenvalue error at each order", st.orders[o].order, err, 0.2 * noise);
            assert_true(md->cmi > 0.99);
            if (st.orders[o].order >= 6) {
                assert_int_equal(st.stability[md - st.modes], OKID_STABLE_ALL);
            }
        }
    }
    free(sws);
    free(ws);
}

/* Field by field: a byte compare would read okid_mode's padding, which nobody writes (valgrind). */
static int same_mode(const okid_mode *a, const okid_mode *b)
{
    return a->eigenvalue.re == b->eigenvalue.re && a->eigenvalue.im == b->eigenvalue.im &&
           a->pole.re == b->pole.re && a->pole.im == b->pole.im && a->frequency_hz == b->frequency_hz &&
           a->damping_ratio == b->damping_ratio && a->is_pair == b->is_pair && a->sensor_shape == b->sensor_shape &&
           a->shape == b->shape && a->emac_output == b->emac_output && a->emac_input == b->emac_input &&
           a->emac == b->emac && a->mpc == b->mpc && a->msv == b->msv && a->cmi == b->cmi;
}

/* Nested truncation is exact: the order-4 entry equals okid_identify() at order 4 on the same data. */
static void test_nested_truncation_equals_direct(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.observer_order = 40;
    cfg.hankel_rows = cfg.hankel_cols = 60;
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(test_identify_noisy(&REF_PAPER, &cfg, PAPER_SAMPLES, 9, 0.02, &id, &ws, &res), OKID_OK);
    size_t bytes = 0;
    void *sws = stab_workspace(&id, 12, 1, &bytes);
    okid_stabilization st;
    assert_int_equal(okid_stabilization_compute(&id, 12, 1, NULL, sws, bytes, &st), OKID_OK);
    assert_int_equal(st.num_orders, 12);
    const okid_stabilization_order *o4 = &st.orders[3];
    assert_int_equal(o4->order, 4);
    assert_int_equal(o4->num_modes, res.num_modes);
    for (int i = 0; i < res.num_modes; ++i) {
        const okid_mode *a = &st.modes[o4->first + i], *b = &res.modes[i];
        assert_relative(a->eigenvalue.re, b->eigenvalue.re, 1e-10, "eigenvalue re", i);
        assert_relative(a->eigenvalue.im, b->eigenvalue.im, 1e-10, "eigenvalue im", i);
        assert_relative(a->damping_ratio, b->damping_ratio, 1e-8, "damping", i);
        assert_relative(a->cmi, b->cmi, 1e-8, "cmi", i);
        assert_relative(a->msv, b->msv, 1e-8, "msv", i);
        assert_true(okid_mac(a->shape, b->shape, 4) > 1 - 1e-12);
    }
    free(sws);
    free(ws);
}

/* Noise-free data: the Hankel matrix has rank 4, so the table stops at order 4. */
static void test_rank_limit(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(test_identify_case(&REF_PAPER, &cfg, PAPER_SAMPLES, 5, &id, &ws, &res), OKID_OK);
    size_t bytes = 0;
    void *sws = stab_workspace(&id, MAX_ORDER, 2, &bytes);
    okid_stabilization st;
    assert_int_equal(okid_stabilization_compute(&id, MAX_ORDER, 2, NULL, sws, bytes, &st), OKID_OK);
    assert_int_equal(st.rank_limit, 4);
    assert_int_equal(st.num_orders, 2);
    free(sws);
    free(ws);
}

static void test_api_contract(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    size_t bytes = 0;
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    okid_stabilization st;
    memset(&id, 0, sizeof id);
    static _Alignas(16) unsigned char sws[OKID_STABILIZATION_WORKSPACE_BYTES(1, 2, 20, 20, 8, 2, 0) + 16];
    size_t need = 0;
    assert_int_equal(okid_stabilization_workspace_size(&id, 8, 2, &need), OKID_E_NOT_INITIALIZED);
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_stabilization_workspace_size(NULL, 8, 2, &need), OKID_E_NULL_POINTER);
    assert_int_equal(okid_stabilization_workspace_size(&id, 8, 2, NULL), OKID_E_NULL_POINTER);
    assert_int_equal(okid_stabilization_workspace_size(&id, 0, 2, &need), OKID_E_BAD_ORDER);
    assert_int_equal(okid_stabilization_workspace_size(&id, 21, 2, &need), OKID_E_BAD_ORDER); /* > min(40, 20) */
    assert_int_equal(okid_stabilization_workspace_size(&id, 8, 0, &need), OKID_E_BAD_SIZE);
    assert_int_equal(okid_stabilization_workspace_size(&id, 8, 9, &need), OKID_E_BAD_SIZE);
    /* The compile-time size is the run-time size, for several shapes. */
    assert_int_equal(okid_stabilization_workspace_size(&id, 8, 2, &need), OKID_OK);
    assert_int_equal(need, OKID_STABILIZATION_WORKSPACE_BYTES(1, 2, 20, 20, 8, 2, 0));
    assert_int_equal(okid_stabilization_workspace_size(&id, 7, 3, &need), OKID_OK);
    assert_int_equal(need, OKID_STABILIZATION_WORKSPACE_BYTES(1, 2, 20, 20, 7, 3, 0));
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, sws, sizeof sws, &st), OKID_E_NOT_AVAILABLE);

    const size_t n = PAPER_SAMPLES;
    okid_real *u = test_white_noise(1, n, 8), *y = malloc(sizeof(okid_real) * 2 * n);
    assert_non_null(y);
    test_simulate(&REF_PAPER, n, u, y, NULL);
    assert_int_equal(okid_push_block(&id, n, u, 1, y, 2, NULL), OKID_OK);
    okid_result res;
    assert_int_equal(okid_identify(&id, &res), OKID_OK);
    const okid_mode first = res.modes[0];
    okid_stabilization_criteria bad;
    assert_int_equal(okid_stabilization_criteria_default(&bad), OKID_OK);
    bad.mac_min = 1.5;
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, &bad, sws, sizeof sws, &st), OKID_E_BAD_PARAMETER);
    bad.mac_min = 0.9;
    bad.frequency_tolerance = NAN;
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, &bad, sws, sizeof sws, &st), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, sws + 8, sizeof sws - 8, &st), OKID_E_WORKSPACE_ALIGNMENT);
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, sws, need - 1, &st), OKID_E_WORKSPACE_TOO_SMALL);
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, NULL, sizeof sws, &st), OKID_E_NULL_POINTER);
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, sws, sizeof sws, NULL), OKID_E_NULL_POINTER);
    assert_int_equal(okid_stabilization_compute(&id, 8, 2, NULL, sws, sizeof sws, &st), OKID_OK);
    /* The identifier's last result is intact, and identifying again gives the same modes. */
    assert_true(same_mode(&res.modes[0], &first));
    okid_result again;
    assert_int_equal(okid_identify(&id, &again), OKID_OK);
    assert_true(again.modes[0].eigenvalue.re == first.eigenvalue.re && again.modes[0].cmi == first.cmi);
    free(u);
    free(y);
    free(ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_true_poles_at_every_order),
        cmocka_unit_test(test_nested_truncation_equals_direct),
        cmocka_unit_test(test_rank_limit),
        cmocka_unit_test(test_api_contract),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
