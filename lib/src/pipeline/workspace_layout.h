/* Configuration checks, derived sizes and the workspace layout of an identifier. */
#ifndef OKID_WORKSPACE_LAYOUT_H
#define OKID_WORKSPACE_LAYOUT_H

#include "okid/identifier.h"

/* Check cfg and derive the sizes. OKID_OK or the specific configuration error. */
okid_status okid_layout_dims(const okid_config *cfg, okid_dims_ *dims);

/*
 * Lay the workspace out for dims (views into base) and return the bytes used. With base NULL it
 * only computes the size: this one function is the definition of okid_workspace_size(). combined and
 * scaled: OKID_REALIZATION_COMBINED and OKID_SCALING_AUTO.
 */
size_t okid_layout_carve(const okid_dims_ *dims, int combined, int scaled, unsigned char *base, okid_views_ *views);

#endif
