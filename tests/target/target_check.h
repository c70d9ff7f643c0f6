/* SPDX-License-Identifier: Apache-2.0 */
/*
 * A tiny assert harness for the target tests (cmocka needs an operating system): each CHECK
 * prints what failed and counts it; main() returns target_summary(), the exit status QEMU reports.
 */
#ifndef OKID_TARGET_CHECK_H
#define OKID_TARGET_CHECK_H

#include <math.h>
#include <stdio.h>

typedef struct target_checks {
    int run, failed;
} target_checks;

/* One harness per program (tests only: libokid has no state). */
static target_checks target_checks_;

static inline void target_check(int ok, const char *what, const char *file, int line)
{
    ++target_checks_.run;
    if (!ok) {
        ++target_checks_.failed;
        printf("FAIL %s:%d: %s\n", file, line, what);
    }
}

/* |got - want| <= tol * scale, printed with both values when it fails. */
static inline void target_check_close(double got, double want, double tol, double scale, const char *what,
                                      const char *file, int line)
{
    const int ok = fabs(got - want) <= tol * scale;
    target_check(ok, what, file, line);
    if (!ok) {
        printf("     got %.17g, want %.17g, |diff| %.3g > %.3g\n", got, want, fabs(got - want), tol * scale);
    }
}

#define CHECK(cond) target_check((cond) != 0, #cond, __FILE__, __LINE__)
#define CHECK_CLOSE(got, want, tol, scale) \
    target_check_close((double)(got), (double)(want), (tol), (scale), #got " ~ " #want, __FILE__, __LINE__)

/* Prints the tally; returns the exit status (0 when every check passed). */
static inline int target_summary(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, target_checks_.run, target_checks_.failed);
    return target_checks_.failed == 0 && target_checks_.run > 0 ? 0 : 1;
}

#endif
