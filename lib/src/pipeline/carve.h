/*
 * Carving a caller's workspace into aligned regions. With a NULL base it only adds up the sizes,
 * so one function both lays out the workspace and computes okid_workspace_size().
 */
#ifndef OKID_CARVE_H
#define OKID_CARVE_H

#include <stddef.h>

#include "okid/types.h"

typedef struct okid_carver {
    unsigned char *base; /* NULL: dry run */
    size_t used;
} okid_carver;

static inline void *okid_carve_bytes(okid_carver *c, size_t bytes)
{
    void *p = (c->base != NULL) ? (void *)(c->base + c->used) : NULL;
    c->used += OKID__ALIGN16(bytes);
    return p;
}

static inline okid_real *okid_carve_reals(okid_carver *c, size_t count)
{
    return (okid_real *)okid_carve_bytes(c, count * sizeof(okid_real));
}

#endif
