/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The automatic identification, written once for okid identify and okid.identify: the settings
 * not given chosen from the record (auto_settings.h), the physical modes over the Hankel windows
 * when the order is not given (auto_modes.h), then the model at the chosen order. The correlation
 * form's guard may refuse (okid/identifier.h): then the QR fold, and OKID_W_CORRELATION_FALLBACK
 * in the result's warnings. No printing: the caller words a failure from `failure`.
 */
#ifndef OKID_HOST_AUTO_IDENTIFY_H
#define OKID_HOST_AUTO_IDENTIFY_H

#include <stddef.h>

#include "auto_modes.h"
#include "auto_settings.h"
#include "okid/okid.h"

/* The model's samples into its identifier: an okid_status (the Python binding feeds in chunks with
   its progress callback; NULL in auto_request: one okid_push_block). */
typedef okid_status (*auto_push_fn)(void *context, okid_identifier *id, size_t n, const okid_real *u,
                                    const okid_real *y);

typedef struct auto_request {
    okid_config cfg;          /* the settings given (num_inputs, num_outputs, dt set); order 0: chosen */
    unsigned given;           /* AUTO_GIVEN_* bits: the settings kept from cfg */
    double observer_seconds;  /* > 0: the observer's span in seconds, counted in K dt once K is chosen */
    double hankel_seconds;    /* > 0: the Hankel window's span in seconds, likewise */
    size_t n;                 /* samples of the record */
    const okid_real *u, *y;   /* r and m values per sample */
    auto_push_fn push;        /* NULL: okid_push_block */
    void *push_context;
} auto_request;

/* Which step failed (AUTO_OK: none). */
typedef enum auto_failure {
    AUTO_OK = 0,
    AUTO_FAILED_HORIZONS,  /* okid_config_horizons refused the spans in seconds */
    AUTO_FAILED_SETTINGS,  /* okid_workspace_size refused the settings (config_explain words it) */
    AUTO_FAILED_DATA,      /* too few samples for the settings: `shortfall` says so */
    AUTO_FAILED_MODES,     /* the main window's identification: its identifier is modes->observers[0].runs[0].id */
    AUTO_FAILED_MODEL,     /* the model's identification: its identifier is `id` */
    AUTO_FAILED_MEMORY     /* no memory for a workspace (the status: OKID_E_WORKSPACE_TOO_SMALL) */
} auto_failure;

typedef struct auto_identification {
    okid_config cfg;       /* the model's settings: chosen ones filled in, least squares after a fallback */
    auto_choice choice;    /* each choice and its numbers (choice.given: the request's bits) */
    auto_modes *modes;     /* the physical modes when the order was chosen, else NULL */
    void *workspace;       /* the model's identifier's (aligned_alloc; the caller may take it over) */
    size_t workspace_bytes;
    okid_identifier id;    /* the model's identifier, over workspace */
    okid_result result;    /* the model (views into workspace) */
    auto_failure failure;
    char shortfall[512];   /* AUTO_FAILED_DATA: the host library's sentence (config_explain.h) */
} auto_identification;

/*
 * Identify rq's record automatically into *out (which auto_identification_free() releases, also
 * after a failure). Returns OKID_OK, or the failing step's status with out->failure naming it.
 */
okid_status auto_identify(const auto_request *rq, auto_identification *out);

/* observer_seconds, hankel_seconds (> 0: given) as counts of K dt into cfg (okid_config_horizons);
   a span not given keeps its count. */
okid_status auto_horizon_seconds(okid_config *cfg, double observer_seconds, double hankel_seconds);

/* The identifier whose counters explain a failure of AUTO_FAILED_MODES or _MODEL (else NULL). */
okid_identifier *auto_failed_identifier(auto_identification *out);

void auto_identification_free(auto_identification *out);

#endif
