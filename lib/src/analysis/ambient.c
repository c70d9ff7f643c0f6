/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Output-only identification (okid/ambient.h): the streaming correlation sums
 * (pipeline/output_correlation), then the same ERA, modal analysis and indicators as
 * okid_identify(), with the references in the role of the inputs and R(k) in that of the system
 * Markov parameters Y_k. One carving (ambient_carve) lays out the workspace and gives its size.
 */
#include "okid/ambient.h"

#include <limits.h>
#include <math.h>

#include "analysis/ambient_internal.h"
#include "numerics/carve.h"
#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "pipeline/era.h"
#include "pipeline/modal_internal.h"
#include "pipeline/output_correlation.h"
#include "quality/modal_indicators_internal.h"

#define OKID_AMBIENT_MAGIC OKID_AMBIENT_MAGIC_

/* Identify's scratch views. */
typedef struct ambient_scratch {
    okid_real *scales; /* nref reference then m output RMS: ERA's channel scales */
    okid_real *obs_last, *ctrl_last;
    /* one region for the phases in turn: ERA, then the modal analysis and the indicators */
    okid_era_scratch era;
    okid_modal_scratch modal;
    okid_indicator_scratch ind;
} ambient_scratch;

/* With segments > 1: one segment's realization and every segment's matched frequency and damping. */
typedef struct ambient_segment_scratch {
    okid_ambient_result_set_ seg;  /* one segment's realization */
    okid_real *seg_f, *seg_z;      /* segments x n: each segment's matched frequency and damping, -1: none */
} ambient_segment_scratch;

/* The layout, in the order of OKID__AMBIENT_WORKSPACE_BYTES64 (sizes.h); NULL base: sizes only. */
/* A result set's model views (the standard deviations apart); set NULL: sizes only. */
static void carve_set(okid_carver *c, uint64_t m, uint64_t nref, uint64_t L, uint64_t n, okid_ambient_result_set_ *set)
{
    const uint64_t k = L * (m < nref ? m : nref);
    okid_real *correlations = okid_carve_reals(c, m * nref * (2u * L + 1u));
    okid_real *sv = okid_carve_reals(c, k);
    okid_real *a = okid_carve_reals(c, n * n);
    okid_real *g = okid_carve_reals(c, n * nref);
    okid_real *cm = okid_carve_reals(c, m * n);
    okid_real *d = okid_carve_reals(c, m * nref);
    okid_mode *modes = (okid_mode *)okid_carve_bytes(c, sizeof(okid_mode) * n);
    okid_complex *shapes = (okid_complex *)okid_carve_bytes(c, sizeof(okid_complex) * n * 3u * m);
    if (set != NULL) {
        set->correlations = correlations;
        set->sv = sv;
        set->a = a;
        set->g = g;
        set->c = cm;
        set->d = d;
        set->modes = modes;
        set->shapes = shapes;
    }
}

/* What outlives identify: the sums and the two result sets. */
static uint64_t carve_persistent(int m_, int nref_, int lags_, int n_, int segments, unsigned char *base,
                                 okid_correlation_sums_ *sums, okid_ambient_result_set_ sets[2])
{
    const uint64_t m = (uint64_t)m_, nref = (uint64_t)nref_, L = (uint64_t)lags_, n = (uint64_t)n_;
    const uint64_t blocks = 2u * L + 1u;
    const uint64_t segs = segments > 1 ? (uint64_t)segments : 1u;
    okid_carver c = {base, 0};
    sums->past.data = okid_carve_reals(&c, nref * 2u * L);
    sums->sums = okid_carve_reals(&c, segs * m * nref * blocks);
    sums->squares = okid_carve_reals(&c, m);
    sums->pairs = (uint64_t *)okid_carve_bytes(&c, 8u * segs * blocks);
    sums->partial = okid_carve_reals(&c, m * nref * blocks + m);
    sums->hist = sums->yblock = NULL;
    if (OKID__AMB_BATCH > 1u) {
        sums->hist = okid_carve_reals(&c, nref * (2u * L + OKID__AMB_BATCH));
        if (nref < m) {
            sums->yblock = okid_carve_reals(&c, m * OKID__AMB_BATCH);
        }
    }
    for (int i = 0; i < 2; ++i) {
        carve_set(&c, m, nref, L, n, &sets[i]);
        sets[i].frequency_std = okid_carve_reals(&c, n);
        sets[i].damping_std = okid_carve_reals(&c, n);
    }
    return c.used;
}

/*
 * Identify's scratch from base (the end of the persistent part): scales, the indicators' blocks,
 * the segments' views (seg may be NULL: not carved), then one region that ERA uses first (H, V',
 * H(1) V_n, column scales, SVD work) and the modal analysis and indicators after it, once ERA's
 * results have been read out (OKID__AMB_SCRATCH_BYTES, the segments' OKID__AMB_SEGMENT_BYTES).
 * NULL base: sizes only.
 */
static uint64_t carve_scratch(int m_, int nref_, int lags_, int n_, int segments, unsigned char *base,
                              ambient_scratch *s, ambient_segment_scratch *seg)
{
    const uint64_t m = (uint64_t)m_, nref = (uint64_t)nref_, L = (uint64_t)lags_, n = (uint64_t)n_;
    const uint64_t hr = L * m, hc = L * nref;
    okid_carver c = {base, 0};
    s->scales = okid_carve_reals(&c, nref + m);
    s->obs_last = okid_carve_reals(&c, m * n);
    s->ctrl_last = okid_carve_reals(&c, n * nref);
    if (segments > 1) {
        if (seg != NULL) {
            seg->seg = (okid_ambient_result_set_){0};
        }
        carve_set(&c, m, nref, L, n, seg != NULL ? &seg->seg : NULL);
        okid_real *f = okid_carve_reals(&c, (uint64_t)segments * n), *z = okid_carve_reals(&c, (uint64_t)segments * n);
        if (seg != NULL) {
            seg->seg_f = f;
            seg->seg_z = z;
        }
    }
    const uint64_t phases = c.used;
    s->era.h = okid_carve_reals(&c, hr * hc);
    s->era.ldh = (int)hr;
    const uint64_t vt_rows = OKID__SVD_VT_ROWS(hr, hc, n);
    s->era.vt = okid_carve_reals(&c, vt_rows * hc);
    s->era.ldvt = vt_rows > 0 ? (int)vt_rows : 1;
    s->era.t = okid_carve_reals(&c, hr * n);
    s->era.col_scale = okid_carve_reals(&c, nref);
    s->era.work = okid_carve_reals(&c, OKID__LWORK_GESVD(hr, hc));
    s->era.leading = 1;
    const uint64_t era_end = c.used;
    c.used = phases;
    okid_carve_modal_phase(&c, n, nref, &s->modal, &s->ind);
    c.used = c.used > era_end ? c.used : era_end;
    return c.used;
}

static uint64_t ambient_carve(int m, int nref, int lags, int n, int segments, okid_correlation_sums_ *sums,
                              okid_ambient_result_set_ sets[2], ambient_scratch *s)
{
    return carve_persistent(m, nref, lags, n, segments, NULL, sums, sets) +
           carve_scratch(m, nref, lags, n, segments, NULL, s, NULL);
}

/* The scratch views of an initialised identifier (seg may be NULL). */
static void scratch_views(const okid_ambient *amb, ambient_scratch *s, ambient_segment_scratch *seg)
{
    (void)carve_scratch(amb->sums_.m, amb->nref_, amb->cfg_.hankel_rows, amb->nmax_, amb->cfg_.segments,
                        amb->scratch_, s, seg);
}

okid_status okid_ambient_config_default(okid_ambient_config *cfg, int num_outputs)
{
    if (cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    *cfg = (okid_ambient_config){0};
    cfg->num_outputs = num_outputs;
    cfg->num_references = 0;
    cfg->hankel_rows = 20;
    cfg->order = 0;
    cfg->dt = 1;
    cfg->sensing = OKID_SENSING_ACCELERATION;
    cfg->segments = 0;
    cfg->segment_samples = 0;
    return OKID_OK;
}

static okid_status refuse(okid_config_issue *issue, okid_status st, const char *field, double value, double lo,
                          double hi)
{
    *issue = (okid_config_issue){field, value, lo, hi};
    return st;
}

/* The configuration's sizes (references resolved) and the order the workspace holds, or the issue. */
static okid_status ambient_dims(const okid_ambient_config *cfg, okid_config_issue *issue, int *nref, int *nmax,
                                int *k)
{
    const int m = cfg->num_outputs;
    if (m < 1 || m > OKID_MAX_DIMENSION) {
        return refuse(issue, OKID_E_BAD_SIZE, "num_outputs", m, 1, OKID_MAX_DIMENSION);
    }
    if (cfg->num_references < 0 || cfg->num_references > m) {
        return refuse(issue, OKID_E_BAD_SIZE, "num_references", cfg->num_references, 0, m);
    }
    for (int l = 0; l < cfg->num_references; ++l) {
        const int lo = l > 0 ? cfg->reference_channels[l - 1] + 1 : 0; /* increasing, so distinct */
        if (cfg->reference_channels[l] < lo || cfg->reference_channels[l] > m - 1) {
            return refuse(issue, OKID_E_BAD_PARAMETER, "reference_channels", cfg->reference_channels[l], lo, m - 1);
        }
    }
    const int L = cfg->hankel_rows;
    /* the Hankel matrix (L m x L r_ref) and its work indexed by int in the backends */
    const int most = OKID_MAX_HORIZON < 46340 / m ? OKID_MAX_HORIZON : 46340 / m;
    if (L < 1 || L > most) {
        return refuse(issue, OKID_E_BAD_SIZE, "hankel_rows", L, 1, most);
    }
    if (!okid_in_magnitude_range(cfg->dt)) {
        return refuse(issue, OKID_E_BAD_PARAMETER, "dt", (double)cfg->dt, (double)OKID_MAGNITUDE_MIN,
                      (double)OKID_MAGNITUDE_MAX);
    }
    const int sensing = (int)cfg->sensing; /* an int: the enumeration may be unsigned (arm-none-eabi) */
    if (sensing < 0 || sensing > 2) {
        return refuse(issue, OKID_E_BAD_PARAMETER, "sensing", sensing, 0, 2);
    }
    *nref = cfg->num_references > 0 ? cfg->num_references : m;
    *k = L * (m < *nref ? m : *nref);
    const int order_max = *k < OKID_MAX_ORDER ? *k : OKID_MAX_ORDER;
    if (cfg->order < 0 || cfg->order > order_max) {
        return refuse(issue, OKID_E_BAD_ORDER, "order", cfg->order, 0, order_max);
    }
#if OKID_LINALG_EIGEN
    if (cfg->order > OKID_EIGEN_MAX_ORDER) { /* the eigen-solver's fixed size, as okid_config_check() */
        return refuse(issue, OKID_E_BAD_ORDER, "order", cfg->order, 0, OKID_EIGEN_MAX_ORDER);
    }
#endif
    *nmax = cfg->order > 0 ? cfg->order : order_max;
    if (cfg->segments < 0 || cfg->segments > OKID_AMBIENT_MAX_SEGMENTS) {
        return refuse(issue, OKID_E_BAD_SIZE, "segments", cfg->segments, 0, OKID_AMBIENT_MAX_SEGMENTS);
    }
    if (cfg->segment_samples < 0 || (cfg->segment_samples > 0 && cfg->segment_samples < 2 * L + 1)) {
        return refuse(issue, OKID_E_BAD_SIZE, "segment_samples", cfg->segment_samples, 2 * L + 1, INT_MAX);
    }
    return OKID_OK;
}

/* Check and size; the carving's total as a size_t. */
static okid_status ambient_size(const okid_ambient_config *cfg, okid_config_issue *issue, size_t *bytes, int *nref,
                                int *nmax, int *k)
{
    okid_status st = ambient_dims(cfg, issue, nref, nmax, k);
    if (st != OKID_OK) {
        return st;
    }
    okid_correlation_sums_ sums;
    okid_ambient_result_set_ sets[2];
    ambient_scratch scratch;
    const uint64_t total = ambient_carve(cfg->num_outputs, *nref, cfg->hankel_rows, *nmax, cfg->segments, &sums, sets,
                                         &scratch);
    st = okid_carve_size(total, bytes);
    if (st != OKID_OK) {
        return refuse(issue, st, "workspace bytes", (double)total, 0, (double)SIZE_MAX);
    }
    return OKID_OK;
}

okid_status okid_ambient_config_check(const okid_ambient_config *cfg, okid_config_issue *issue)
{
    if (cfg == NULL || issue == NULL) {
        return OKID_E_NULL_POINTER;
    }
    *issue = (okid_config_issue){NULL, 0, 0, 0};
    size_t bytes = 0;
    int nref = 0, nmax = 0, k = 0;
    return ambient_size(cfg, issue, &bytes, &nref, &nmax, &k);
}

okid_status okid_ambient_workspace_size(const okid_ambient_config *cfg, size_t *bytes)
{
    if (cfg == NULL || bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    okid_config_issue issue;
    int nref = 0, nmax = 0, k = 0;
    return ambient_size(cfg, &issue, bytes, &nref, &nmax, &k);
}

static int ambient_ready(const okid_ambient *amb)
{
    return amb->magic_ == OKID_AMBIENT_MAGIC;
}

okid_status okid_ambient_init(okid_ambient *amb, const okid_ambient_config *cfg, void *workspace, size_t bytes,
                              size_t *bytes_needed)
{
    if (amb == NULL || cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    amb->magic_ = 0;
    okid_config_issue issue;
    size_t needed = 0;
    int nref = 0, nmax = 0, k = 0;
    const okid_status st = ambient_size(cfg, &issue, &needed, &nref, &nmax, &k);
    if (st != OKID_OK) {
        return st;
    }
    if (bytes_needed != NULL) {
        *bytes_needed = needed;
    }
    if (workspace == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (((uintptr_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    if (bytes < needed) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    amb->cfg_ = *cfg;
    amb->nref_ = nref;
    amb->nmax_ = nmax;
    amb->k_ = k;
    amb->workspace_ = (unsigned char *)workspace;
    okid_correlation_sums_ *s = &amb->sums_;
    amb->scratch_ = amb->workspace_ + (size_t)carve_persistent(cfg->num_outputs, nref, cfg->hankel_rows, nmax,
                                                               cfg->segments, amb->workspace_, s, amb->set_);
    s->m = cfg->num_outputs;
    s->nref = nref;
    s->lags = 2 * cfg->hankel_rows;
    s->segments = cfg->segments > 1 ? cfg->segments : 1;
    s->block = cfg->segment_samples > 0 ? cfg->segment_samples : 20 * (s->lags + 1);
    for (int l = 0; l < nref; ++l) {
        s->refs[l] = cfg->num_references > 0 ? cfg->reference_channels[l] : l;
    }
    s->past.width = nref;
    s->past.depth = s->lags;
    s->batch = (int)OKID__AMB_BATCH;
    s->ldh = s->lags + s->batch;
    amb->magic_ = OKID_AMBIENT_MAGIC;
    return okid_ambient_reset(amb);
}

okid_status okid_ambient_reset(okid_ambient *amb)
{
    if (amb == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!ambient_ready(amb)) {
        return OKID_E_NOT_INITIALIZED;
    }
    okid_corr_clear(&amb->sums_);
    amb->samples_ = 0;
    amb->current_ = 0;
    amb->has_result_ = 0;
    return OKID_OK;
}

okid_status okid_ambient_push(okid_ambient *amb, const okid_real *y)
{
    if (amb == NULL || y == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!ambient_ready(amb)) {
        return OKID_E_NOT_INITIALIZED;
    }
#if OKID__AMB_BATCH > 1
    okid_corr_batch_end(&amb->sums_); /* after push_block: its pending samples summed, the ring refilled */
#endif
    for (int a = 0; a < amb->sums_.m; ++a) {
        if (!okid_is_finite(y[a])) {
            okid_corr_gap(&amb->sums_);
            return OKID_E_NONFINITE_SAMPLE;
        }
    }
    okid_corr_add(&amb->sums_, y);
    ++amb->samples_;
    return OKID_OK;
}

#if OKID__AMB_BATCH > 1
/* How many of the count rows at y (row t at y + t ldy, m values) are finite before the first that is not. */
static size_t finite_rows(int m, size_t count, const okid_real *y, size_t ldy)
{
    for (size_t t = 0; t < count; ++t) {
        for (int a = 0; a < m; ++a) {
            if (!okid_is_finite(y[t * ldy + (size_t)a])) {
                return t;
            }
        }
    }
    return count;
}
#endif

okid_status okid_ambient_push_block(okid_ambient *amb, size_t count, const okid_real *y, size_t ldy,
                                    size_t *accepted)
{
    if (amb == NULL || (y == NULL && count > 0)) {
        return OKID_E_NULL_POINTER;
    }
    if (!ambient_ready(amb)) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (ldy < (size_t)amb->sums_.m) {
        return OKID_E_BAD_SIZE;
    }
    size_t good = 0;
    okid_correlation_sums_ *s = &amb->sums_;
#if OKID__AMB_BATCH == 1
    (void)s; /* the Eigen backend (the firmware's): count pushes */
    for (size_t t = 0; t < count; ++t) {
        good += okid_ambient_push(amb, y + t * ldy) == OKID_OK;
    }
#else
    {
        /* the same samples, gaps and segments as count pushes; the products summed in batches */
        okid_corr_batch_begin(s);
        size_t t = 0;
        while (t < count) {
            const size_t run = finite_rows(s->m, count - t, y + t * ldy, ldy);
            okid_corr_batch_add_rows(s, run, y + t * ldy, ldy);
            good += run;
            t += run;
            if (t < count) { /* a sample with a NaN or Inf: a gap */
                okid_corr_batch_gap(s);
                ++t;
            }
        }
        amb->samples_ += good;
    }
#endif
    if (accepted != NULL) {
        *accepted = good;
    }
    return good == count ? OKID_OK : OKID_E_NONFINITE_SAMPLE;
}

/* ERA's channel scales: each reference's and each output's RMS (1 for a zero channel). */
static okid_status channel_scales(const okid_correlation_sums_ *s, const okid_real *rms, okid_real *scales)
{
    for (int a = 0; a < s->m; ++a) {
        if (rms[a] > 0 && !okid_in_magnitude_range(rms[a])) {
            return OKID_E_DATA_RANGE;
        }
    }
    for (int l = 0; l < s->nref; ++l) {
        scales[l] = rms[s->refs[l]] > 0 ? rms[s->refs[l]] : 1;
    }
    for (int a = 0; a < s->m; ++a) {
        scales[s->nref + a] = rms[a] > 0 ? rms[a] : 1;
    }
    return OKID_OK;
}

void okid_ambient_era_scratch_(const okid_ambient *amb, okid_era_scratch *era)
{
    ambient_scratch s;
    scratch_views(amb, &s, NULL);
    *era = s.era;
    era->t = NULL;
    era->vt = NULL;
}

okid_status okid_ambient_scales_(const okid_ambient *amb, okid_real *scales)
{
    okid_real *rms = scales + amb->nref_; /* the outputs' RMS, then scales in place */
    okid_corr_rms(&amb->sums_, rms);
    return channel_scales(&amb->sums_, rms, scales);
}

/* ERA at `requested` (0: the largest gap), modes and indicators into set from its correlations; the scratch is s. */
static okid_status realize_modes(const okid_ambient *amb, int requested, okid_ambient_result_set_ *set,
                                 const ambient_scratch *s, unsigned *warnings, int *order, int *num_modes)
{
    const int m = amb->sums_.m, nref = amb->nref_, L = amb->cfg_.hankel_rows;
    const okid_era_problem problem = {nref, m, nref, L, L, requested, amb->nmax_, set->correlations, NULL,
                                      s->scales};
    const okid_era_output out = {set->sv, set->a, set->g, set->c, set->d, NULL};
    okid_status st = okid_era_realize(&problem, &s->era, &out, order, warnings);
    if (st != OKID_OK) {
        return st;
    }
    const int n = *order;
    okid_indicators_capture(&problem, &s->era, set->sv, n, s->obs_last, s->ctrl_last);
    st = okid_modal_compute(n, m, set->a, n, set->c, m, amb->cfg_.dt, amb->cfg_.sensing, &s->modal, set->shapes,
                            set->modes, num_modes, warnings);
    if (st != OKID_OK) {
        return st;
    }
    const okid_indicator_inputs in = {n, m, nref, L, L, set->g, n, set->c, m, s->obs_last, m, s->ctrl_last, n};
    return okid_modal_indicators(&in, s->modal.vr, s->modal.wr, s->modal.wi, &s->ind, set->modes, *num_modes);
}

/* The pair of modes[0..count) nearest in frequency to f within 20 %, or NULL. */
static const okid_mode *nearest_pair(const okid_mode *modes, int count, okid_real f)
{
    const okid_mode *best = NULL;
    for (int i = 0; i < count; ++i) {
        if (modes[i].is_pair && okid_fabs(modes[i].frequency_hz - f) <= OKID_R(0.2) * f &&
            (best == NULL || okid_fabs(modes[i].frequency_hz - f) < okid_fabs(best->frequency_hz - f))) {
            best = &modes[i];
        }
    }
    return best;
}

/* Standard error of the mean of the values >= 0 among x[0], x[stride], ... (count of them): NaN below two. */
static okid_real standard_error(const okid_real *x, int count, int stride)
{
    okid_real sum = 0, squares = 0;
    int c = 0;
    for (int j = 0; j < count; ++j) {
        if (x[(size_t)j * (size_t)stride] >= 0) sum += x[(size_t)j * (size_t)stride], ++c;
    }
    if (c < 2) {
        return (okid_real)NAN;
    }
    const okid_real mean = sum / (okid_real)c;
    for (int j = 0; j < count; ++j) {
        const okid_real v = x[(size_t)j * (size_t)stride];
        if (v >= 0) squares += (v - mean) * (v - mean);
    }
    return okid_sqrt(squares / ((okid_real)c * (okid_real)(c - 1)));
}

/*
 * Each segment's correlations realized at the record's order n, their modes matched to the
 * record's pairs (the nearest within 20 % in frequency): the standard deviations of set's modes
 * as the standard error of the segments' mean. Returns the segments realized; a segment whose
 * realization fails (too few pairs, rank deficient at n) counts for none of the modes.
 */
static int segment_spread(const okid_ambient *amb, okid_ambient_result_set_ *set, const ambient_scratch *s, int n,
                          int num_modes)
{
    const okid_correlation_sums_ *sums = &amb->sums_;
    const int m = sums->m, nref = amb->nref_, L = amb->cfg_.hankel_rows, segs = sums->segments;
    ambient_scratch dry;
    ambient_segment_scratch views;
    scratch_views(amb, &dry, &views);
    const okid_ambient_result_set_ *seg = &views.seg;
    const okid_era_problem problem = {nref, m, nref, L, L, n, amb->nmax_, seg->correlations, NULL, s->scales};
    const okid_era_output out = {seg->sv, seg->a, seg->g, seg->c, seg->d, NULL};
    int used = 0;
    for (int j = 0; j < segs; ++j) {
        okid_real *f = views.seg_f + (size_t)j * (size_t)n, *z = views.seg_z + (size_t)j * (size_t)n;
        for (int i = 0; i < num_modes; ++i) {
            f[i] = z[i] = -1;
        }
        if (okid_corr_pairs(sums, j, sums->lags) == 0) {
            continue;
        }
        okid_corr_estimate(sums, j, sums->lags, seg->correlations);
        int order = 0, count = 0;
        unsigned ignored = 0;
        if (okid_era_realize(&problem, &s->era, &out, &order, &ignored) != OKID_OK ||
            okid_modal_compute(n, m, seg->a, n, seg->c, m, amb->cfg_.dt, amb->cfg_.sensing, &s->modal, seg->shapes,
                               seg->modes, &count, &ignored) != OKID_OK) {
            continue;
        }
        ++used;
        for (int i = 0; i < num_modes; ++i) {
            const okid_mode *near = set->modes[i].is_pair ? nearest_pair(seg->modes, count, set->modes[i].frequency_hz)
                                                          : NULL;
            if (near != NULL) {
                f[i] = near->frequency_hz;
                z[i] = near->damping_ratio >= 0 ? near->damping_ratio : -1; /* an unstable pole is no estimate */
            }
        }
    }
    for (int i = 0; i < num_modes; ++i) {
        set->frequency_std[i] = standard_error(views.seg_f + i, segs, n);
        set->damping_std[i] = standard_error(views.seg_z + i, segs, n);
    }
    return used;
}

/* okid_ambient_identify() at `requested` (0: the largest gap), validated by the callers. */
static okid_status identify_at(okid_ambient *amb, int requested, okid_ambient_result *result)
{
    const okid_correlation_sums_ *sums = &amb->sums_;
    const uint64_t pairs = okid_corr_pairs(sums, -1, sums->lags);
    if (pairs == 0) {
        return OKID_E_NOT_ENOUGH_DATA;
    }
    /* the set the last good result is not in: a failure leaves that one as it was */
    const int next = amb->has_result_ ? 1 - amb->current_ : amb->current_;
    okid_ambient_result_set_ *set = &amb->set_[next];
    ambient_scratch s;
    scratch_views(amb, &s, NULL);
    okid_corr_estimate(sums, -1, sums->lags, set->correlations);
    okid_status st = okid_ambient_scales_(amb, s.scales);
    if (st != OKID_OK) {
        return st;
    }
    unsigned warnings = 0;
    int n = 0, num_modes = 0;
    st = realize_modes(amb, requested, set, &s, &warnings, &n, &num_modes);
    if (st != OKID_OK) {
        return st;
    }
    for (int i = 0; i < num_modes; ++i) {
        if (!okid_is_finite(set->modes[i].frequency_hz) || !okid_is_finite(set->modes[i].damping_ratio)) {
            return OKID_E_DATA_RANGE;
        }
    }
    const int used = sums->segments > 1 ? segment_spread(amb, set, &s, n, num_modes) : 0;
    const int m = sums->m, nref = amb->nref_, blocks = sums->lags + 1;
    const okid_real condition = set->sv[0] / set->sv[n - 1];
    if (condition > 1 / okid_sqrt(OKID_EPSILON)) {
        warnings |= OKID_W_REALIZATION_ILL_CONDITIONED;
    }
    set->result = (okid_ambient_result){
        .order = n,
        .num_modes = num_modes,
        .modes = set->modes,
        .A = {set->a, n, n, n},
        .C = {set->c, m, n, m},
        .G = {set->g, n, nref, n},
        .correlations = {set->correlations, m, nref * blocks, m},
        .singular_values = set->sv,
        .num_singular_values = amb->k_,
        .realization_condition = condition,
        .dt = amb->cfg_.dt,
        .samples = amb->samples_,
        .pairs = pairs,
        .warnings = warnings,
        .frequency_std = sums->segments > 1 ? set->frequency_std : NULL,
        .damping_std = sums->segments > 1 ? set->damping_std : NULL,
        .segments_used = used,
    };
    amb->current_ = next;
    amb->has_result_ = 1;
    *result = set->result;
    return OKID_OK;
}

okid_status okid_ambient_identify(okid_ambient *amb, okid_ambient_result *result)
{
    if (amb == NULL || result == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!ambient_ready(amb)) {
        return OKID_E_NOT_INITIALIZED;
    }
    return identify_at(amb, amb->cfg_.order, result);
}

okid_status okid_ambient_identify_order(okid_ambient *amb, int order, okid_ambient_result *result)
{
    if (amb == NULL || result == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!ambient_ready(amb)) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (order < 1 || order > amb->nmax_) {
        return OKID_E_BAD_ORDER;
    }
    return identify_at(amb, order, result);
}
