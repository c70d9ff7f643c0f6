/* SPDX-License-Identifier: Apache-2.0 */
/* The modal parameters the two linear-algebra backends must agree on (test_backend_agreement). */
#ifndef OKID_BACKEND_VALUES_H
#define OKID_BACKEND_VALUES_H

/* One compared number: what it is, its value, the scale its difference is relative to, and the
   tolerance of that relative difference (1e-9 in double; in float the one test_support.h derives
   for the quantity, doubled: each backend may sit on either side of the truth). */
typedef struct backend_value {
    char name[48];
    double value, scale, tol;
} backend_value;

enum { BACKEND_MAX_VALUES = 1024 };

/*
 * Identifies the paper, MIMO and 3-DOF reference cases noise-free, as test_identify_accuracy does,
 * with whichever backend the program links, and lists every mode's eigenvalue, frequency, damping,
 * sensor shape and accuracy indicators in a fixed order. Returns the count.
 */
int backend_case_values(backend_value *values, int max);

#endif
