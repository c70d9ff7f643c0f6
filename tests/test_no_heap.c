/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Proves at run time that the paper case (init, 1001 pushes, identify) allocates nothing: this
 * program replaces malloc and friends (glibc lets an executable interpose them for every shared
 * object too, LAPACK and BLAS included) and counts the calls made while the library runs.
 * Skipped under AddressSanitizer, which owns the allocator.
 */
#include "test_support.h"

#include <stdlib.h>

#if defined(__SANITIZE_ADDRESS__)
#define OKID_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OKID_TEST_UNDER_ASAN 1
#endif
#endif

#ifndef OKID_TEST_UNDER_ASAN
void *__libc_malloc(size_t size);
void *__libc_calloc(size_t count, size_t size);
void *__libc_realloc(void *ptr, size_t size);
void *__libc_memalign(size_t alignment, size_t size);
void __libc_free(void *ptr);

static volatile int counting;
static volatile long heap_calls;

static void count_call(void)
{
    if (counting) {
        ++heap_calls;
    }
}

void *malloc(size_t size)
{
    count_call();
    return __libc_malloc(size);
}

void *calloc(size_t count, size_t size)
{
    count_call();
    return __libc_calloc(count, size);
}

void *realloc(void *ptr, size_t size)
{
    count_call();
    return __libc_realloc(ptr, size);
}

void *aligned_alloc(size_t alignment, size_t size)
{
    count_call();
    return __libc_memalign(alignment, size);
}

int posix_memalign(void **out, size_t alignment, size_t size); /* POSIX: not declared in strict C11 */

int posix_memalign(void **out, size_t alignment, size_t size)
{
    count_call();
    *out = __libc_memalign(alignment, size);
    return *out ? 0 : 12; /* ENOMEM */
}

void free(void *ptr)
{
    count_call();
    __libc_free(ptr);
}
#endif

#ifdef OKID_TEST_UNDER_ASAN
static void test_paper_case_allocates_nothing(void **state)
{
    (void)state;
    skip();
}

static void test_quality_options_allocate_nothing(void **state)
{
    (void)state;
    skip();
}
#else
enum { SAMPLES = 1001 };
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char workspace[OKID_WORKSPACE_BYTES(1, 2, 20, 20, 20, 4, 0, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char stab_workspace[OKID_STABILIZATION_WORKSPACE_BYTES(1, 2, 20, 20, 8, 2, 0)];
static okid_real force[SAMPLES], accelerations[2 * SAMPLES];

static void test_paper_case_allocates_nothing(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    okid_rng rng;
    okid_rng_seed(&rng, 2024);
    okid_rng_normal(&rng, 1, SAMPLES, force, 1);
    test_simulate(&REF_PAPER, SAMPLES, force, accelerations, NULL);

    /* The counter must see an allocation when there is one, or this test could not fail. */
    counting = 1;
    void *volatile probe = malloc(16); /* volatile: the compiler may not elide the pair */
    free(probe);
    counting = 0;
    assert_int_equal(heap_calls, 2);
    heap_calls = 0;

    okid_identifier id;
    okid_result res;
    counting = 1;
    const okid_status init = okid_init(&id, &cfg, workspace, sizeof workspace, NULL);
    okid_status push = OKID_OK;
    for (int k = 0; k < SAMPLES && push == OKID_OK; ++k) {
        push = okid_push(&id, &force[k], &accelerations[2 * k]);
    }
    const okid_status identify = okid_identify(&id, &res);
    okid_stabilization st;
    const okid_status stab = okid_stabilization_compute(&id, 8, 2, NULL, stab_workspace, sizeof stab_workspace, &st);
    counting = 0;
    assert_int_equal(stab, OKID_OK);
    assert_int_equal(init, OKID_OK);
    assert_int_equal(push, OKID_OK);
    assert_int_equal(identify, OKID_OK);
    assert_int_equal(heap_calls, 0);
    assert_int_equal(res.num_modes, 2);
}

/* Decimation, scaling and instrumental variables: the filter design at init, the filtering and
   scaling on push, the instruments' cross-product and its factorisation on identify. */
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char options_workspace[OKID_WORKSPACE_BYTES_OPTIONS(
    1, 2, 10, 10, 10, 4, 0, 0, 2, OKID_SCALING_AUTO, OKID_ESTIMATOR_INSTRUMENTAL, 0)];

static void test_quality_options_allocate_nothing(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.observer_order = 10;
    cfg.hankel_rows = cfg.hankel_cols = 10;
    cfg.decimation = 2;
    cfg.scaling = OKID_SCALING_AUTO;
    cfg.estimator = OKID_ESTIMATOR_INSTRUMENTAL;
    okid_rng rng;
    okid_rng_seed(&rng, 7);
    okid_rng_normal(&rng, 1, SAMPLES, force, 1);
    test_simulate(&REF_PAPER, SAMPLES, force, accelerations, NULL);
    heap_calls = 0;
    okid_identifier id;
    okid_result res;
    counting = 1;
    const okid_status init = okid_init(&id, &cfg, options_workspace, sizeof options_workspace, NULL);
    const okid_status push = okid_push_block(&id, SAMPLES, force, 1, accelerations, 2, NULL);
    const okid_status identify = okid_identify(&id, &res);
    counting = 0;
    assert_int_equal(init, OKID_OK);
    assert_int_equal(push, OKID_OK);
    assert_int_equal(identify, OKID_OK);
    assert_int_equal(heap_calls, 0);
    assert_int_equal(res.decimation, 2);
    assert_non_null(res.output_scales);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_paper_case_allocates_nothing),
                                       cmocka_unit_test(test_quality_options_allocate_nothing)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
