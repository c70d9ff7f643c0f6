/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The LAPACK side of test_backend_agreement: writes the reference cases' modal parameters, as
 * identified by the LAPACK backend (this program links libokid), to BACKEND_VALUES_FILE (or argv[1]).
 */
#include <stdio.h>

#include "backend_values.h"
#include "test_support.h"

static const char *out_path;

static void test_write_values(void **state)
{
    (void)state;
    static backend_value values[BACKEND_MAX_VALUES];
    const int count = backend_case_values(values, BACKEND_MAX_VALUES);
    FILE *out = fopen(out_path, "w");
    assert_non_null(out);
    for (int i = 0; i < count; ++i) {
        fprintf(out, "%s %a\n", values[i].name, values[i].value);
    }
    assert_int_equal(fclose(out), 0);
}

int main(int argc, char **argv)
{
    out_path = argc > 1 ? argv[1] : BACKEND_VALUES_FILE; /* the file of this build, or another one */
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_write_values)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
