/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Both linear-algebra backends on the paper, MIMO and 3-DOF cases and the output-only paper case
 * (backend_values.c): this program links the Eigen
 * build of the core (okid_eigen) and compares its modal parameters with those the LAPACK build
 * wrote to BACKEND_VALUES_FILE (backend_values_lapacke, run first as a ctest fixture): to 1e-9
 * relative in double, in float to twice the tolerances the accuracy tests hold each backend to.
 * The two builds cannot share one process (they define the same okid_* symbols).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "backend_values.h"
#include "test_support.h"

static const char *lapacke_path;

static void test_backends_agree(void **state)
{
    (void)state;
    static backend_value eigen[BACKEND_MAX_VALUES];
    const int count = backend_case_values(eigen, BACKEND_MAX_VALUES);
    FILE *in = fopen(lapacke_path, "r");
    assert_non_null(in);
    double worst = 0, worst_tol = 1; /* the difference closest to its tolerance */
    int compared = 0;
    char name[64];
    double lapacke = 0;
    while (fscanf(in, "%63s %la", name, &lapacke) == 2) {
        assert_true(compared < count);
        const backend_value *e = &eigen[compared++];
        if (strcmp(name, e->name) != 0) {
            fail_msg("record %d: LAPACK wrote %s, Eigen computed %s", compared, name, e->name);
        }
        const double diff = fabs(e->value - lapacke) / (e->scale > 0 ? e->scale : 1);
        check_within_at(__FILE__, __LINE__, "Eigen against LAPACK", compared, diff, e->tol);
        if (e->tol > 0 && diff / e->tol > worst / worst_tol) {
            worst = diff;
            worst_tol = e->tol;
        }
    }
    fclose(in);
    assert_int_equal(compared, count);
    printf("%d values of 4 cases (singular values, modal parameters): Eigen vs LAPACK within %.2g of tolerance (difference %.2g, tolerance %.1e)\n",
           compared, worst / worst_tol, worst, worst_tol);
}

int main(int argc, char **argv)
{
    lapacke_path = argc > 1 ? argv[1] : BACKEND_VALUES_FILE; /* the file of this build, or another one */
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_backends_agree)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
