/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file ambient_storage.h
 * \brief NOT API: the members of okid_ambient (okid/ambient.h), complete only so that firmware can
 *        allocate the struct statically. Do not touch them: they change without notice. Included
 *        at the end of okid/ambient.h, whose types it uses.
 */
#ifndef OKID_AMBIENT_STORAGE_H
#define OKID_AMBIENT_STORAGE_H

#include <stdint.h>

#include "okid/correlation_storage.h"

/* One result set of okid_ambient_identify(). */
typedef struct okid_ambient_result_set_ {
    okid_real *correlations, *sv, *a, *g, *c, *d;
    okid_real *frequency_std, *damping_std; /* NULL in the segment scratch */
    okid_mode *modes;
    okid_complex *shapes;
    okid_ambient_result result;
} okid_ambient_result_set_;

struct okid_ambient {
    uint32_t magic_;
    okid_ambient_config cfg_;
    int nref_, nmax_, k_;           /* references, the order the workspace holds, Hankel rank limit */
    unsigned char *workspace_;
    unsigned char *scratch_;        /* identify's scratch: the workspace past the sums and result sets */
    okid_correlation_sums_ sums_;
    okid_ambient_result_set_ set_[2];
    int current_;                   /* the set holding the last good result */
    int has_result_;
    uint64_t samples_;
};

#endif
