/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Prediction-error refinement streamed over the record (refine.h): the workspace, the passes
 * (simulation, forward sensitivities, normal equations) and the Levenberg-Marquardt steps between
 * them. The cost is the Gaussian negative log-likelihood with an unknown noise variance per
 * output, V = (N/2) sum_i log(s_i / N), s_i the output's residual sum of squares; its Gauss-Newton
 * matrix weighs output i by N / s_i. A pass only knows s_i at its end, so the normal matrix it
 * accumulates uses the weights of the last accepted pass, while the gradient is accumulated per
 * output and weighed exactly: the fixed point is the maximum-likelihood estimate. The innovation
 * form feeds the residual back through K, so every parameter moves the whole state: its
 * sensitivities are n-vectors, psi(k+1) = A psi + (dA x + dB u + dK e) - K dyhat, with
 * dyhat = C psi + dC x + dD u.
 */
#include "analysis/refine_internal.h"

#include "numerics/carve.h"
#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "okid/identifier.h"

#define OKID_REFINE_MAGIC 0x6f6b7266u /* "okrf" */
#define OKID_REFINE_MU_START OKID_R(1e-3)
#define OKID_REFINE_MU_MIN OKID_R(1e-9)
#define OKID_REFINE_MU_MAX OKID_R(1e10)

okid_status okid_refine_config_default(okid_refine_config *cfg)
{
    if (cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    cfg->max_passes = OKID_REFINE_MAX_PASSES;
    cfg->step_tolerance = OKID_REFINE_STEP_TOLERANCE;
    cfg->refine_model = OKID_REFINE_OUTPUT_ERROR;
    return OKID_OK;
}

const char *okid_refine_model_str(okid_refine_model model)
{
    switch (model) {
    case OKID_REFINE_OUTPUT_ERROR: return "output_error";
    case OKID_REFINE_INNOVATION: return "innovation";
    }
    return "unknown";
}

const char *okid_refine_state_str(okid_refine_state state)
{
    switch (state) {
    case OKID_REFINE_NEED_PASS: return "another pass over the record is needed";
    case OKID_REFINE_CONVERGED: return "converged";
    case OKID_REFINE_DIVERGED: return "diverged: the model's predictions are not finite over the record";
    case OKID_REFINE_NOT_IMPROVING: return "stopped: no damped step lowers the cost";
    case OKID_REFINE_ITERATION_LIMIT: return "stopped: max_passes reached before convergence";
    }
    return "unknown refinement state";
}

/* Lay out the workspace (base NULL: only count); inn: the innovation form. */
static size_t layout(okid_refiner *rf, void *base, int inn, int n, int r, int m)
{
    const size_t np = (size_t)OKID__REFINE_NP64(inn, n, r, m), nn = (size_t)n, rr = (size_t)r, mm = (size_t)m;
    const size_t scratch = (size_t)OKID__REFINE_SCRATCH(n, np); /* fits: okid_refine_workspace_size() checked */
    okid_carver c = {(unsigned char *)base, 0};
    rf->ptab_ = (int *)okid_carve_bytes(&c, sizeof(int) * 4u * np);
    rf->blk_ = (int *)okid_carve_bytes(&c, sizeof(int) * OKID_RB_INTS * nn);
    rf->theta_best_ = okid_carve_reals(&c, np);
    rf->theta_ = okid_carve_reals(&c, np);
    rf->lam_re_ = okid_carve_reals(&c, nn);
    rf->lam_im_ = okid_carve_reals(&c, nn);
    rf->b_ = okid_carve_reals(&c, nn * rr);
    rf->c_ = okid_carve_reals(&c, mm * nn);
    rf->d_ = okid_carve_reals(&c, mm * rr);
    rf->x0_ = okid_carve_reals(&c, nn);
    rf->x_ = okid_carve_reals(&c, nn);
    rf->sens_ = okid_carve_reals(&c, (inn ? nn : 2u) * np);
    rf->jrow_ = okid_carve_reals(&c, mm * np);
    rf->nrm_[0] = okid_carve_reals(&c, scratch);
    rf->nrm_[1] = okid_carve_reals(&c, scratch);
    rf->grad_ = okid_carve_reals(&c, mm * np);
    rf->grad_best_ = okid_carve_reals(&c, np);
    rf->step_ = okid_carve_reals(&c, np);
    rf->diag_ = okid_carve_reals(&c, np);
    rf->ss_ = okid_carve_reals(&c, mm);
    rf->yy_ = okid_carve_reals(&c, mm);
    rf->weight_ = okid_carve_reals(&c, mm);
    rf->rms_start_ = okid_carve_reals(&c, mm);
    rf->rms_ = okid_carve_reals(&c, mm);
    rf->e_ = okid_carve_reals(&c, mm);
    rf->wj_ = okid_carve_reals(&c, mm);
    rf->a_full_ = okid_carve_reals(&c, nn * nn);
    rf->modes_ = (okid_mode *)okid_carve_bytes(&c, sizeof(okid_mode) * nn);
    rf->mode_std_ = (okid_mode_std *)okid_carve_bytes(&c, sizeof(okid_mode_std) * nn);
    rf->shapes_ = (okid_complex *)okid_carve_bytes(&c, sizeof(okid_complex) * nn * 3u * mm);
    rf->shape_std_ = (okid_complex *)okid_carve_bytes(&c, sizeof(okid_complex) * nn * mm);
    const size_t lags = (size_t)OKID_REFINE_LAGS;
    rf->lag_ring_ = okid_carve_reals(&c, mm * lags);
    rf->acf_ = okid_carve_reals(&c, mm * lags);
    rf->acf_best_ = okid_carve_reals(&c, mm * lags);
    rf->ysum_ = okid_carve_reals(&c, mm);
    rf->whiteness_ = okid_carve_reals(&c, mm);
    rf->max_acf_ = okid_carve_reals(&c, mm);
    rf->fit_ = okid_carve_reals(&c, mm);
    rf->out_warn_ = (unsigned *)okid_carve_bytes(&c, sizeof(unsigned) * mm);
    rf->grad_mark_ = okid_carve_reals(&c, mm * np);
    rf->score_[0] = okid_carve_reals(&c, np * np);
    rf->score_[1] = okid_carve_reals(&c, np * np);
    rf->score_sum_ = okid_carve_reals(&c, np);
    rf->u_ring_ = okid_carve_reals(&c, rr * lags);
    rf->ccf_ = okid_carve_reals(&c, mm * rr * lags);
    rf->ccf_best_ = okid_carve_reals(&c, mm * rr * lags);
    rf->uacf_ = okid_carve_reals(&c, rr * lags);
    rf->usum_ = okid_carve_reals(&c, rr);
    rf->esum_ = okid_carve_reals(&c, mm);
    rf->esum_best_ = okid_carve_reals(&c, mm);
    rf->xcorr_ = okid_carve_reals(&c, mm * rr);
    rf->max_xcorr_ = okid_carve_reals(&c, mm * rr);
    rf->xcorr_band_ = okid_carve_reals(&c, mm * rr);
    rf->k_ = inn ? okid_carve_reals(&c, nn * mm) : NULL;
    return c.used;
}

/* The workspace of accepted dimensions can exceed the address space of a 32-bit target: counted
 * in 64 bits first, so that layout()'s size_t arithmetic never wraps. */
static int refine_size_fits(int inn, int n, int r, int m)
{
    return OKID__REFINE_MODEL_WORKSPACE_BYTES64(inn, n, r, m) <= (unsigned long long)(size_t)-1;
}

okid_status okid_refine_workspace_size(int n, int r, int m, size_t *bytes)
{
    return okid_refine_model_workspace_size(OKID_REFINE_OUTPUT_ERROR, n, r, m, bytes);
}

okid_status okid_refine_model_workspace_size(okid_refine_model model, int n, int r, int m, size_t *bytes)
{
    if (bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if ((unsigned)model > (unsigned)OKID_REFINE_INNOVATION) {
        return OKID_E_BAD_PARAMETER;
    }
    const int inn = model == OKID_REFINE_INNOVATION;
    if (n < 1 || n > OKID_MAX_ORDER || r < 1 || r > OKID_MAX_DIMENSION || m < 1 || m > OKID_MAX_DIMENSION) {
        return OKID_E_BAD_SIZE;
    }
    if (!refine_size_fits(inn, n, r, m)) {
        return OKID_E_BAD_SIZE;
    }
    okid_refiner dry;
    *bytes = layout(&dry, NULL, inn, n, r, m);
    return OKID_OK;
}

okid_status okid_refine_init(okid_refiner *rf, const okid_refine_config *cfg, const okid_result *start,
                             okid_sensing sensing, void *workspace, size_t bytes, size_t *bytes_needed)
{
    if (rf == NULL || cfg == NULL || start == NULL || workspace == NULL) {
        return OKID_E_NULL_POINTER;
    }
    rf->magic_ = 0;
    if (start->A.data == NULL || start->B.data == NULL || start->C.data == NULL || start->D.data == NULL) {
        return OKID_E_NULL_POINTER;
    }
    const int n = start->order, r = start->B.cols, m = start->C.rows;
    const int inn = cfg->refine_model == OKID_REFINE_INNOVATION;
    if (n < 1 || n > OKID_MAX_ORDER || r < 1 || r > OKID_MAX_DIMENSION || m < 1 || m > OKID_MAX_DIMENSION ||
        start->A.rows != n || start->A.cols != n || start->B.rows != n || start->C.cols != n ||
        start->D.rows != m || start->D.cols != r || start->A.ld < n || start->B.ld < n || start->C.ld < m ||
        start->D.ld < m || !refine_size_fits(inn, n, r, m)) {
        return OKID_E_BAD_SIZE;
    }
    if (cfg->max_passes < 0 || cfg->max_passes == 1 || cfg->max_passes > 1000 ||
        !okid_is_finite(cfg->step_tolerance) || cfg->step_tolerance < 0 || !okid_is_finite(start->dt) ||
        start->dt <= 0 || (unsigned)sensing > 2u || !okid_all_finite(n, n, start->A.data, start->A.ld) ||
        !okid_all_finite(n, r, start->B.data, start->B.ld) || !okid_all_finite(m, n, start->C.data, start->C.ld) ||
        !okid_all_finite(m, r, start->D.data, start->D.ld) || (unsigned)cfg->refine_model > (unsigned)OKID_REFINE_INNOVATION) {
        return OKID_E_BAD_PARAMETER;
    }
    /* the observer gain starts the innovation form: one of the right shape must be finite */
    if (inn && start->G.data != NULL && start->G.rows == n && start->G.cols == m &&
        (start->G.ld < n || !okid_all_finite(n, m, start->G.data, start->G.ld))) {
        return OKID_E_BAD_PARAMETER;
    }
    const size_t need = layout(rf, NULL, inn, n, r, m);
    if (bytes_needed != NULL) {
        *bytes_needed = need;
    }
    if (bytes < need) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    if (((size_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    (void)layout(rf, workspace, inn, n, r, m);
    rf->cfg_ = *cfg;
    if (rf->cfg_.max_passes == 0) {
        rf->cfg_.max_passes = OKID_REFINE_MAX_PASSES;
    }
    if (rf->cfg_.step_tolerance == 0) {
        rf->cfg_.step_tolerance = OKID_REFINE_STEP_TOLERANCE;
    }
    rf->n_ = n;
    rf->r_ = r;
    rf->m_ = m;
    rf->sensing_ = sensing;
    rf->dt_ = start->dt;
    rf->best_ = 0; /* the modal form's stability test uses nrm_[1 - best_] */
    const okid_status st = okid_refine_modal_form(rf, start);
    if (st != OKID_OK) {
        return st;
    }
    okid_refine_apply(rf, rf->theta_);
    rf->state_ = OKID_REFINE_NEED_PASS;
    rf->passes_ = rf->iterations_ = rf->in_pass_ = rf->finished_ = rf->noise_fixed_ = 0;
    rf->noise_scale_ = 1;
    rf->std_status_ = OKID_E_NOT_AVAILABLE;
    rf->best_ = 0;
    rf->mu_ = OKID_REFINE_MU_START;
    rf->cost_best_ = 0;
    rf->decrement_ = -1;
    rf->samples_ = rf->pass_samples_ = 0;
    rf->warnings_ = rf->test_warnings_ = 0;
    rf->num_modes_ = 0;
    rf->split_[0] = rf->split_[1] = -1;
    rf->covariance_ = OKID_REFINE_COVARIANCE_FISHER;
    rf->score_ok_[0] = rf->score_ok_[1] = 0;
    rf->block_len_ = 0;
    for (int i = 0; i < m; ++i) {
        rf->weight_[i] = 1;
        rf->rms_start_[i] = rf->rms_[i] = 0;
        rf->whiteness_[i] = rf->max_acf_[i] = rf->fit_[i] = -1;
        rf->out_warn_[i] = 0;
    }
    for (int k = 0; k < m * r; ++k) {
        rf->xcorr_[k] = rf->max_xcorr_[k] = rf->xcorr_band_[k] = -1;
    }
    rf->magic_ = OKID_REFINE_MAGIC;
    return OKID_OK;
}

static okid_status check(const okid_refiner *rf)
{
    if (rf == NULL) {
        return OKID_E_NULL_POINTER;
    }
    return rf->magic_ == OKID_REFINE_MAGIC ? OKID_OK : OKID_E_NOT_INITIALIZED;
}

okid_status okid_refine_set_noise(okid_refiner *rf, const okid_real *noise_std)
{
    okid_status st = check(rf);
    if (st != OKID_OK) {
        return st;
    }
    if (noise_std == NULL) {
        return OKID_E_NULL_POINTER;
    }
    okid_real largest = 0;
    for (int i = 0; i < rf->m_; ++i) {
        if (!okid_is_finite(noise_std[i]) || !(noise_std[i] > 0)) {
            return OKID_E_BAD_PARAMETER;
        }
        largest = noise_std[i] > largest ? noise_std[i] : largest;
    }
    /* the bound is linear in the noise: weigh relative to a power of two (exact scaling) so that
       1 / sigma^2 neither overflows nor underflows */
    okid_real scale = 1;
    while (scale <= largest / 2) {
        scale *= 2;
    }
    while (scale > largest) {
        scale /= 2;
    }
    for (int i = 0; i < rf->m_; ++i) {
        const okid_real rel = noise_std[i] / scale;
        if (!okid_is_finite(1 / (rel * rel))) {
            return OKID_E_BAD_PARAMETER;
        }
    }
    if (rf->passes_ > 0 || rf->in_pass_ || rf->finished_) {
        return OKID_E_NOT_AVAILABLE;
    }
    for (int i = 0; i < rf->m_; ++i) {
        const okid_real rel = noise_std[i] / scale;
        rf->weight_[i] = 1 / (rel * rel);
    }
    rf->noise_scale_ = scale;
    rf->noise_fixed_ = 1;
    rf->passes_ = 1; /* no residual pass: the weights are known */
    return OKID_OK;
}

/* Pass 1 measures residuals only; later passes also accumulate the Jacobian. */
static int jacobian_pass(const okid_refiner *rf)
{
    return rf->passes_ > 0;
}

okid_status okid_refine_begin_pass(okid_refiner *rf)
{
    okid_status st = check(rf);
    if (st != OKID_OK) {
        return st;
    }
    if (rf->finished_) {
        return OKID_E_NOT_AVAILABLE;
    }
    const int n = rf->n_, m = rf->m_, np = rf->np_;
    for (int i = 0; i < n; ++i) {
        rf->x_[i] = rf->x0_[i];
    }
    /* sensitivities: d x(0) / d x0 = e_row, every other one starts at zero (output error: the
       two entries of the parameter's block; innovation form: all n) */
    const int inn = OKID_REFINE_IS_INNOVATION(rf);
    for (int p = 0; p < np; ++p) {
        const int *t = rf->ptab_ + 4 * p;
        if (inn) {
            okid_real *s = rf->sens_ + (size_t)p * (size_t)n;
            for (int i = 0; i < n; ++i) {
                s[i] = 0;
            }
            if (t[0] == OKID_RP_X0) {
                s[t[2]] = 1;
            }
            continue;
        }
        rf->sens_[2 * p] = rf->sens_[2 * p + 1] = 0;
        if (t[0] == OKID_RP_X0) {
            rf->sens_[2 * p + (t[2] - rf->blk_[OKID_RB_INTS * t[1] + OKID_RB_FIRST])] = 1;
        }
    }
    okid_real *nrm = rf->nrm_[1 - rf->best_];
    for (size_t k = 0; k < (size_t)np * (size_t)np; ++k) {
        nrm[k] = 0;
    }
    for (size_t k = 0; k < (size_t)m * (size_t)np; ++k) {
        rf->grad_[k] = 0;
    }
    for (int i = 0; i < m; ++i) {
        rf->ss_[i] = rf->yy_[i] = 0;
    }
    rf->pass_samples_ = 0;
    rf->samples_used_ = 0;
    okid_refine_tests_begin_pass(rf);
    rf->in_pass_ = 1;
    return OKID_OK;
}

/* The output derivatives of one sample: jrow (m x np) = d yhat / d theta. */
static void output_jacobian(okid_refiner *rf, const okid_real *u)
{
    const int m = rf->m_, np = rf->np_;
    for (int p = 0; p < np; ++p) {
        const int *t = rf->ptab_ + 4 * p;
        okid_real *col = rf->jrow_ + (size_t)p * (size_t)m;
        for (int i = 0; i < m; ++i) {
            col[i] = 0;
        }
        switch (t[0]) {
        case OKID_RP_C: col[t[2]] = rf->x_[t[3]]; break;
        case OKID_RP_D: col[t[2]] = u[t[3]]; break;
        default: break;
        }
        if (OKID_REFINE_IS_INNOVATION(rf)) {
            /* every parameter moves the whole state through K: C psi, psi the parameter's n-vector */
            const int n = rf->n_;
            const okid_real *s = rf->sens_ + (size_t)p * (size_t)n;
            for (int j = 0; j < n; ++j) {
                if (s[j] != 0) {
                    for (int i = 0; i < m; ++i) {
                        col[i] += OKID_AT(rf->c_, m, i, j) * s[j];
                    }
                }
            }
            continue;
        }
        switch (t[0]) {
        case OKID_RP_C:
        case OKID_RP_D: break;
        default: {
            const int *b = rf->blk_ + OKID_RB_INTS * t[1];
            const int first = b[OKID_RB_FIRST], size = b[OKID_RB_SIZE];
            for (int i = 0; i < m; ++i) {
                col[i] = OKID_AT(rf->c_, m, i, first) * rf->sens_[2 * p] +
                         (size == 2 ? OKID_AT(rf->c_, m, i, first + 1) * rf->sens_[2 * p + 1] : 0);
            }
        }
        }
    }
}

/* N += J' W J (upper triangle), grad_i += J_i' e_i. */
static void accumulate(okid_refiner *rf, const okid_real *e)
{
    const int m = rf->m_, np = rf->np_;
    okid_real *nrm = rf->nrm_[1 - rf->best_], *wjq = rf->wj_;
    for (int q = 0; q < np; ++q) {
        const okid_real *jq = rf->jrow_ + (size_t)q * (size_t)m;
        int nonzero = 0;
        for (int i = 0; i < m; ++i) {
            wjq[i] = rf->weight_[i] * jq[i];
            nonzero |= jq[i] != 0;
            rf->grad_[(size_t)i * (size_t)np + (size_t)q] += jq[i] * e[i];
        }
        if (!nonzero) {
            continue;
        }
        okid_real *nq = nrm + (size_t)q * (size_t)np;
        for (int p = 0; p <= q; ++p) {
            const okid_real *jp = rf->jrow_ + (size_t)p * (size_t)m;
            okid_real sum = 0;
            for (int i = 0; i < m; ++i) {
                sum += jp[i] * wjq[i];
            }
            nq[p] += sum;
        }
    }
}

/*
 * The innovation form's step of the sensitivities, with x(k), u(k), the residual e(k) and the
 * output derivatives jrow_ of this sample (e NULL: no output this sample, the predictor runs open
 * loop and e and its derivatives are 0): psi(k+1) = A psi + dA x + dB u + dK e - K dyhat.
 */
static void advance_innovation_sensitivities(okid_refiner *rf, const okid_real *u, const okid_real *e)
{
    const int n = rf->n_, m = rf->m_, np = rf->np_;
    for (int p = 0; p < np; ++p) {
        const int *t = rf->ptab_ + 4 * p;
        okid_real *s = rf->sens_ + (size_t)p * (size_t)n;
        for (int k = 0; k < rf->nblocks_; ++k) {
            const int first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
            const okid_real a = rf->lam_re_[k], b = rf->lam_im_[k];
            if (rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE] == 2) {
                const okid_real s0 = s[first], s1 = s[first + 1];
                s[first] = a * s0 + b * s1;
                s[first + 1] = -b * s0 + a * s1;
            } else {
                s[first] *= a;
            }
        }
        const int first = t[0] <= OKID_RP_X0 ? rf->blk_[OKID_RB_INTS * t[1] + OKID_RB_FIRST] : 0;
        switch (t[0]) {
        case OKID_RP_LAMBDA_RE:
            s[first] += rf->x_[first];
            if (rf->blk_[OKID_RB_INTS * t[1] + OKID_RB_SIZE] == 2) {
                s[first + 1] += rf->x_[first + 1];
            }
            break;
        case OKID_RP_LAMBDA_IM:
            s[first] += rf->x_[first + 1];
            s[first + 1] -= rf->x_[first];
            break;
        case OKID_RP_B: s[t[2]] += u[t[3]]; break;
        case OKID_RP_K: s[t[2]] += e != NULL ? e[t[3]] : 0; break;
        default: break;
        }
        if (e == NULL) {
            continue;
        }
        const okid_real *dy = rf->jrow_ + (size_t)p * (size_t)m;
        for (int i = 0; i < m; ++i) {
            if (dy[i] != 0) {
                for (int j = 0; j < n; ++j) {
                    s[j] -= OKID_AT(rf->k_, n, j, i) * dy[i];
                }
            }
        }
    }
}

/* Advance the sensitivities (with x(k)) and then the state, by one sample; e: the sample's
   residual, NULL when its output is not finite (the innovation form then runs open loop). */
static void advance(okid_refiner *rf, const okid_real *u, const okid_real *e)
{
    const int n = rf->n_, r = rf->r_, np = rf->np_;
    if (jacobian_pass(rf) && OKID_REFINE_IS_INNOVATION(rf)) {
        advance_innovation_sensitivities(rf, u, e);
    } else if (jacobian_pass(rf)) {
        for (int p = 0; p < np; ++p) {
            const int *t = rf->ptab_ + 4 * p;
            if (t[0] >= OKID_RP_C) {
                break; /* C and D move no state and come last */
            }
            const int k = t[1], first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
            const int size = rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE];
            const okid_real a = rf->lam_re_[k], b = rf->lam_im_[k];
            okid_real *s = rf->sens_ + 2 * p;
            okid_real s0 = a * s[0] + (size == 2 ? b * s[1] : 0);
            okid_real s1 = size == 2 ? -b * s[0] + a * s[1] : 0;
            switch (t[0]) {
            case OKID_RP_LAMBDA_RE:
                s0 += rf->x_[first];
                s1 += size == 2 ? rf->x_[first + 1] : 0;
                break;
            case OKID_RP_LAMBDA_IM:
                s0 += rf->x_[first + 1];
                s1 -= rf->x_[first];
                break;
            case OKID_RP_B:
                if (t[2] == first) {
                    s0 += u[t[3]];
                } else {
                    s1 += u[t[3]];
                }
                break;
            default: break;
            }
            s[0] = s0;
            s[1] = s1;
        }
    }
    for (int k = 0; k < rf->nblocks_; ++k) {
        const int first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST], size = rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE];
        const okid_real a = rf->lam_re_[k], b = rf->lam_im_[k];
        okid_real bu0 = 0, bu1 = 0;
        for (int j = 0; j < r; ++j) {
            bu0 += OKID_AT(rf->b_, n, first, j) * u[j];
            bu1 += size == 2 ? OKID_AT(rf->b_, n, first + 1, j) * u[j] : 0;
        }
        const okid_real x0 = rf->x_[first], x1 = size == 2 ? rf->x_[first + 1] : 0;
        if (size == 2) {
            rf->x_[first] = a * x0 + b * x1 + bu0;
            rf->x_[first + 1] = -b * x0 + a * x1 + bu1;
        } else {
            rf->x_[first] = a * x0 + bu0;
        }
    }
    if (rf->k_ != NULL && e != NULL) {
        for (int i = 0; i < rf->m_; ++i) {
            for (int j = 0; j < n; ++j) {
                rf->x_[j] += OKID_AT(rf->k_, n, j, i) * e[i];
            }
        }
    }
}

okid_status okid_refine_push_block(okid_refiner *rf, size_t count, const okid_real *u, size_t ldu,
                                   const okid_real *y, size_t ldy)
{
    okid_status st = check(rf);
    if (st != OKID_OK) {
        return st;
    }
    if (u == NULL || y == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (ldu < (size_t)rf->r_ || ldy < (size_t)rf->m_) {
        return OKID_E_BAD_SIZE;
    }
    if (!rf->in_pass_ || rf->finished_) {
        return OKID_E_NOT_AVAILABLE;
    }
    const int n = rf->n_, r = rf->r_, m = rf->m_;
    for (size_t k = 0; k < count; ++k) {
        const okid_real *uk = u + k * ldu, *yk = y + k * ldy;
        for (int j = 0; j < r; ++j) {
            if (!okid_is_finite(uk[j])) {
                rf->in_pass_ = 0; /* the pass is void; the accepted state is untouched */
                return OKID_E_NONFINITE_SAMPLE;
            }
        }
        int use = 1;
        for (int i = 0; i < m; ++i) {
            use &= okid_is_finite(yk[i]);
        }
        if (use) {
            okid_real *e = rf->e_;
            for (int i = 0; i < m; ++i) {
                okid_real yhat = 0;
                for (int j = 0; j < n; ++j) {
                    yhat += OKID_AT(rf->c_, m, i, j) * rf->x_[j];
                }
                for (int j = 0; j < r; ++j) {
                    yhat += OKID_AT(rf->d_, m, i, j) * uk[j];
                }
                e[i] = yk[i] - yhat;
                rf->ss_[i] += e[i] * e[i];
                rf->yy_[i] += yk[i] * yk[i];
            }
            okid_refine_tests_sample(rf, e, yk, uk);
            if (jacobian_pass(rf)) {
                output_jacobian(rf, uk);
                accumulate(rf, e);
            }
            ++rf->samples_used_;
            if (rf->score_ok_[1 - rf->best_] && rf->samples_used_ % rf->block_len_ == 0) {
                okid_refine_tests_close_block(rf);
            }
        }
        advance(rf, uk, use ? rf->e_ : NULL);
        ++rf->pass_samples_;
    }
    return OKID_OK;
}

/* Stop: the best model, its covariance and modes. */
static void finish(okid_refiner *rf, okid_refine_state state)
{
    rf->state_ = state;
    rf->finished_ = 1;
    okid_refine_apply(rf, rf->theta_best_);
    okid_refine_tests_finish(rf, state == OKID_REFINE_DIVERGED);
    /* a failure here leaves no modes (num_modes 0) but the model stands */
    const okid_status st = okid_refine_modes_and_std(rf, state != OKID_REFINE_DIVERGED);
    if (st != OKID_OK) {
        rf->num_modes_ = 0;
        rf->std_status_ = st;
    }
    okid_refine_find_split(rf);
    rf->warnings_ |= rf->test_warnings_;
}

/* Propose theta_ = theta_best_ + the damped step; 0 when the damping ran out. */
static int propose(okid_refiner *rf)
{
    const int np = rf->np_;
    okid_real *spare = rf->nrm_[1 - rf->best_];
    while (rf->mu_ <= OKID_REFINE_MU_MAX) {
        if (okid_refine_damped_solve(np, rf->nrm_[rf->best_], rf->mu_, rf->grad_best_, spare, rf->diag_, rf->step_)) {
            for (int p = 0; p < np; ++p) {
                rf->theta_[p] = rf->theta_best_[p] + rf->step_[p];
            }
            okid_refine_apply(rf, rf->theta_);
            if (okid_refine_stable(rf)) {
                return 1;
            }
        }
        rf->mu_ *= 10;
    }
    return 0;
}

/* The undamped Gauss-Newton decrement g' N^-1 g at the accepted point. */
static okid_real decrement(okid_refiner *rf)
{
    const int np = rf->np_;
    if (!okid_refine_damped_solve(np, rf->nrm_[rf->best_], 0, rf->grad_best_, rf->nrm_[1 - rf->best_], rf->diag_,
                                   rf->step_)) {
        return -1; /* singular: not converged by this test */
    }
    okid_real dec = 0;
    for (int p = 0; p < np; ++p) {
        dec += rf->step_[p] * rf->grad_best_[p];
    }
    return dec;
}

okid_status okid_refine_end_pass(okid_refiner *rf, okid_refine_state *state)
{
    okid_status st = check(rf);
    if (st != OKID_OK) {
        return st;
    }
    if (state == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!rf->in_pass_ || rf->finished_) {
        return OKID_E_NOT_AVAILABLE;
    }
    rf->in_pass_ = 0;
    const int m = rf->m_, np = rf->np_;
    if (rf->samples_ > 0 && rf->pass_samples_ != rf->samples_) {
        return OKID_E_BAD_SIZE;
    }
    if (rf->samples_used_ * (uint64_t)m <= (uint64_t)np) {
        return OKID_E_NOT_ENOUGH_DATA;
    }
    if (rf->score_ok_[1 - rf->best_] && rf->samples_used_ % rf->block_len_ != 0) {
        okid_refine_tests_close_block(rf); /* the last, shorter block */
    }
    const okid_real used = (okid_real)rf->samples_used_;
    okid_real cost = 0;
    for (int i = 0; i < m; ++i) {
        /* a noise-free fit is as good as round-off: no log(0) */
        const okid_real floor = OKID_EPSILON * OKID_EPSILON * rf->yy_[i] + OKID_REAL_MIN;
        if (rf->ss_[i] < floor) {
            rf->ss_[i] = floor;
        }
        cost += rf->noise_fixed_ ? rf->ss_[i] * rf->weight_[i] : used * okid_log(rf->ss_[i] / used);
    }
    cost /= 2;
    const int finite = okid_is_finite(cost);
    if (rf->samples_ == 0) {
        rf->samples_ = rf->pass_samples_; /* the first pass sets the record's length */
    }

    if (rf->passes_ == 0) { /* the residual pass of the start model */
        rf->passes_ = 1;
        rf->cost_best_ = cost; /* not finite when diverged */
        if (!finite) {
            finish(rf, OKID_REFINE_DIVERGED);
        } else {
            okid_refine_tests_accept(rf);
            for (int i = 0; i < m; ++i) {
                rf->weight_[i] = used / rf->ss_[i];
                rf->rms_start_[i] = rf->rms_[i] = okid_sqrt(rf->ss_[i] / used);
            }
        }
        *state = rf->state_;
        return OKID_OK;
    }

    ++rf->passes_;
    const int first_jacobian = rf->passes_ == 2;
    if (finite && (first_jacobian || cost < rf->cost_best_)) {
        rf->best_ = 1 - rf->best_;
        rf->cost_best_ = cost;
        okid_refine_tests_accept(rf);
        for (int p = 0; p < np; ++p) {
            rf->theta_best_[p] = rf->theta_[p];
            okid_real g = 0;
            for (int i = 0; i < m; ++i) {
                const okid_real w = rf->noise_fixed_ ? rf->weight_[i] : used / rf->ss_[i];
                g += w * rf->grad_[(size_t)i * (size_t)np + (size_t)p];
            }
            rf->grad_best_[p] = g;
        }
        for (int i = 0; i < m; ++i) {
            rf->weight_[i] = rf->noise_fixed_ ? rf->weight_[i] : used / rf->ss_[i];
            rf->rms_[i] = okid_sqrt(rf->ss_[i] / used);
            if (first_jacobian && rf->noise_fixed_) {
                rf->rms_start_[i] = rf->rms_[i];
            }
        }
        if (!first_jacobian) {
            ++rf->iterations_;
            rf->mu_ = rf->mu_ / 10 < OKID_REFINE_MU_MIN ? OKID_REFINE_MU_MIN : rf->mu_ / 10;
        }
        /* noise-free data: once the model reproduces the record to round-off the steps are round-off too */
        int exact = 1;
        for (int i = 0; i < m; ++i) {
            exact &= rf->ss_[i] <= (1000 * OKID_EPSILON) * (1000 * OKID_EPSILON) * rf->yy_[i];
        }
        const okid_real dec = decrement(rf);
        /* the decrement of the cost in units of the noise (the weights are relative to noise_scale_) */
        rf->decrement_ = dec >= 0 ? dec / rf->noise_scale_ / rf->noise_scale_ : -1;
        if (exact || (dec >= 0 && rf->decrement_ < rf->cfg_.step_tolerance)) {
            finish(rf, OKID_REFINE_CONVERGED);
            *state = rf->state_;
            return OKID_OK;
        }
    } else {
        rf->mu_ *= 10;
    }
    if (rf->passes_ >= rf->cfg_.max_passes) {
        finish(rf, OKID_REFINE_ITERATION_LIMIT);
    } else if (!propose(rf)) {
        finish(rf, rf->iterations_ == 0 && !finite ? OKID_REFINE_DIVERGED : OKID_REFINE_NOT_IMPROVING);
    }
    *state = rf->state_;
    return OKID_OK;
}

okid_status okid_refine_get_result(const okid_refiner *rf, okid_refine_result *result)
{
    okid_status st = check(rf);
    if (st != OKID_OK) {
        return st;
    }
    if (result == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!rf->finished_) {
        return OKID_E_NOT_AVAILABLE;
    }
    const int n = rf->n_, r = rf->r_, m = rf->m_;
    result->state = rf->state_;
    result->passes = rf->passes_;
    result->iterations = rf->iterations_;
    result->num_parameters = rf->np_;
    result->order = n;
    result->num_modes = rf->num_modes_;
    result->modes = rf->modes_;
    result->mode_std = rf->mode_std_;
    result->A = (okid_matrix){rf->a_full_, n, n, n};
    result->B = (okid_matrix){rf->b_, n, r, n};
    result->C = (okid_matrix){rf->c_, m, n, m};
    result->D = (okid_matrix){rf->d_, m, r, m};
    result->refine_model = rf->cfg_.refine_model;
    result->K = (okid_matrix){rf->k_, n, rf->k_ != NULL ? m : 0, n};
    result->initial_state = rf->x0_;
    result->residual_rms_start = rf->rms_start_;
    result->residual_rms = rf->rms_;
    result->cost = rf->cost_best_ / rf->noise_scale_ / rf->noise_scale_;
    result->decrement = rf->decrement_;
    result->dt = rf->dt_;
    result->samples = rf->samples_;
    result->warnings = rf->warnings_;
    result->split_modes[0] = rf->split_[0];
    result->split_modes[1] = rf->split_[1];
    result->std_status = rf->std_status_;
    result->output_warnings = rf->out_warn_;
    result->whiteness = rf->whiteness_;
    result->max_autocorrelation = rf->max_acf_;
    result->fit_percent = rf->fit_;
    result->input_correlation = rf->xcorr_;
    result->max_input_correlation = rf->max_xcorr_;
    result->input_correlation_band = rf->xcorr_band_;
    result->autocorrelation_band = rf->samples_used_ > 0 ? OKID_R(1.96) / okid_sqrt((okid_real)rf->samples_used_) : -1;
    result->covariance = rf->covariance_;
    return OKID_OK;
}
