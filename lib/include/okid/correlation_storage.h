/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file correlation_storage.h
 * \brief NOT API: the streaming sums of the output correlations that an output-only identifier
 *        keeps (okid/ambient_storage.h), for the pipeline stage that updates them.
 */
#ifndef OKID_CORRELATION_STORAGE_H
#define OKID_CORRELATION_STORAGE_H

#include <stdint.h>

#include "okid/limits.h"
#include "okid/ring_storage.h"
#include "okid/types.h"

/* The streaming sums of the output correlations (pipeline/output_correlation.h). */
typedef struct okid_correlation_sums_ {
    int m, nref, lags;           /* outputs, references, largest lag 2L */
    int segments, block;         /* sums kept apart: sample t adds to segment (t / block) mod segments */
    uint64_t added;              /* samples added since the last clear */
    int refs[OKID_MAX_DIMENSION]; /* the nref reference outputs */
    okid_ring_ past;             /* the last 2L reference vectors (nref values each) */
    okid_real *sums;             /* S(0..2L) of each segment: m x nref (2L + 1) each, leading dimension m */
    okid_real *squares;          /* m: sum of y_a(t)^2 */
    uint64_t *pairs;             /* 2L + 1 per segment: products summed at each lag */
    /* okid_corr_add()'s run of up to OKID__CORR_RUN samples, summed apart from the sums and added
       to them at its end (or where the segment changes): in float the sums of a long record
       then keep their digits (docs/ambient.md, "Limits"). */
    okid_real *partial;          /* m x nref (2L + 1): the run's S(0..2L), then its m squares */
    int partial_count;           /* samples in the run */
    int partial_segment;         /* the segment the run adds to */
    /* okid_ambient_push_block()'s batches (OKID__AMB_BATCH samples; NULL with a batch of 1): */
    int batch;                   /* samples summed per matrix product */
    int batching;                /* 1 while hist, not the ring, holds the last references */
    int pending, held;           /* samples of the batch in hist; valid lags before it (0..2L) */
    int batch_segment;           /* the segment the pending samples add to */
    int ldh;                     /* 2L + batch: the history's leading dimension */
    okid_real *hist;             /* nref rows of ldh: the 2L reference samples before the batch
                                    (zeros where none is held), then the batch's, oldest first */
    okid_real *yblock;           /* m rows of batch: the batch's outputs (NULL when every output is a
                                    reference: they are hist's rows then) */
} okid_correlation_sums_;

#endif
