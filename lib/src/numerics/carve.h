/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Carving a caller's workspace into aligned regions. With a NULL base it only adds up the sizes,
 * so one function both lays out the workspace and computes okid_workspace_size().
 *
 * Sizes add up in 64 bits whatever size_t is: on a 32-bit target the sum of accepted dimensions
 * can exceed 4 GiB, and a sum that wrapped around would hand okid_init() a workspace too small for
 * what it then writes. okid_carve_size() turns the 64-bit total into a size_t or refuses it.
 */
#ifndef OKID_CARVE_H
#define OKID_CARVE_H

#include <stddef.h>
#include <stdint.h>

#include "okid/status.h"
#include "okid/types.h"

typedef struct okid_carver {
    unsigned char *base; /* NULL: dry run */
    uint64_t used;
} okid_carver;

static inline void *okid_carve_bytes(okid_carver *c, uint64_t bytes)
{
    /* with a base the total was checked by okid_carve_size() first, so used fits in size_t */
    void *p = (c->base != NULL) ? (void *)(c->base + (size_t)c->used) : NULL;
    c->used += (bytes + 15u) / 16u * 16u;
    return p;
}

static inline okid_real *okid_carve_reals(okid_carver *c, uint64_t count)
{
    return (okid_real *)okid_carve_bytes(c, count * sizeof(okid_real));
}

/* A 64-bit total as a size_t: OKID_OK, or OKID_E_BAD_SIZE when it exceeds the address space. */
static inline okid_status okid_carve_size(uint64_t total, size_t *bytes)
{
    if (total > (uint64_t)SIZE_MAX) {
        return OKID_E_BAD_SIZE;
    }
    *bytes = (size_t)total;
    return OKID_OK;
}

#endif
