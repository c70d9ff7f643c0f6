/* SPDX-License-Identifier: Apache-2.0 */
/* Identifiability diagnostics: see diagnostics.h and the warning bits of okid/status.h. */
#include "quality/diagnostics.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "numerics/triangular_lstsq.h"
#include "pipeline/least_squares.h"

/* Only modes this consistent count as identified for the Hankel-span rule. */
#define SPAN_MIN_CMI OKID_R(0.5)
/* "About one period" (docs/design.md, numerical decisions): the span may fall short of the slowest period by this factor. */
#define SPAN_PERIOD_FRACTION OKID_R(0.9)

static okid_real ratio_or_inf(okid_real largest, okid_real smallest)
{
    return smallest > 0 ? largest / smallest : (okid_real)INFINITY;
}

/*
 * |R|_1 |R^-1|_1 of the leading cols x cols block of R diag(1 / scale), R upper triangular: R^-1
 * column by column by back substitution into x (cols reals). Exact, O(cols^3 / 6), no extra memory
 * beyond x; +inf for a zero pivot or an inverse beyond the range of okid_real.
 */
static okid_real triangular_condition(const okid_real *r, int ldr, int cols, const okid_real *scale, okid_real *x)
{
    okid_real norm = 0, inverse_norm = 0;
    for (int j = 0; j < cols; ++j) {
        okid_real column = 0;
        for (int i = 0; i <= j; ++i) {
            column += okid_fabs(OKID_AT(r, ldr, i, j)) / scale[j];
        }
        norm = column > norm ? column : norm;
    }
    for (int j = 0; j < cols; ++j) {
        okid_real column = 0;
        for (int i = j; i >= 0; --i) {
            okid_real sum = (i == j) ? 1 : 0;
            for (int k = i + 1; k <= j; ++k) {
                sum -= OKID_AT(r, ldr, i, k) / scale[k] * x[k];
            }
            const okid_real pivot = OKID_AT(r, ldr, i, i) / scale[i];
            if (pivot == 0) {
                return (okid_real)INFINITY;
            }
            x[i] = sum / pivot;
            column += okid_fabs(x[i]);
        }
        if (!okid_is_finite(column)) { /* overflow, or inf - inf */
            return (okid_real)INFINITY;
        }
        inverse_norm = column > inverse_norm ? column : inverse_norm;
    }
    return norm * inverse_norm;
}

okid_status okid_diagnose_regressor(int q, int nu, okid_real *r, int ldr, okid_real tol, int n, int regressor_rank,
                                    const okid_lsq_scratch *scratch, okid_regressor_diagnostics *out,
                                    unsigned *warnings)
{
    const okid_real gap = okid_sqrt(tol);
    okid_lsq_column_norms(r, ldr, q, scratch->scale);

    out->input_condition = triangular_condition(r, ldr, nu, scratch->scale, scratch->column);
    if (out->input_condition * gap > 1) {
        *warnings |= OKID_W_WEAK_EXCITATION;
    }
    out->lsq_condition = triangular_condition(r, ldr, q, scratch->scale, scratch->column);

    const int model_rank = nu + n;
    out->expected_rank = model_rank < q ? model_rank : q;
    if (regressor_rank < out->expected_rank) {
        *warnings |= OKID_W_RANK_BELOW_MODEL;
    }
    if (model_rank >= q) {
        return OKID_OK;
    }
    /* Noise lifts the regressor's rank past the model's r (p + 1) + n at any tolerance; (near)
       noise-free data keeps it there even at the looser tolerance sqrt(tol). */
    okid_real *s = okid_lsq_equilibrated_copy(r, ldr, q, scratch->scale);
    const int loose_rank = okid_lsq_equilibrated_rank_up_to(q, s, ldr, gap, model_rank + 1, scratch);
    if (loose_rank <= model_rank) {
        *warnings |= OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM;
    }
    return OKID_OK;
}

void okid_diagnose_realization(const okid_real *sv, int n, okid_real span, const okid_mode *modes, int num_modes,
                               okid_real *condition, unsigned *warnings)
{
    *condition = ratio_or_inf(sv[0], sv[n - 1]);
    if (*condition * okid_sqrt(OKID_EPSILON) > 1) {
        *warnings |= OKID_W_REALIZATION_ILL_CONDITIONED;
    }
    okid_real slowest = 0; /* Hz; 0 = no consistent oscillating mode */
    for (int i = 0; i < num_modes; ++i) {
        const okid_mode *md = &modes[i];
        if (md->is_pair && okid_cabs(md->eigenvalue) < 1 && md->cmi >= SPAN_MIN_CMI &&
            (slowest == 0 || md->frequency_hz < slowest)) {
            slowest = md->frequency_hz;
        }
    }
    if (slowest > 0 && span * slowest < SPAN_PERIOD_FRACTION) {
        *warnings |= OKID_W_HANKEL_SPAN_SHORT;
    }
}
