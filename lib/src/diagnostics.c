/* Identifiability diagnostics: see diagnostics.h and the warning bits of okid/status.h. */
#include "diagnostics.h"

#include "dense.h"
#include "least_squares.h"
#include "linalg.h"
#include "real_math.h"

/* Only modes this consistent count as identified for the Hankel-span rule. */
#define SPAN_MIN_CMI OKID_R(0.5)
/* "About one period" (DESIGN.md): the span may fall short of the slowest period by this factor. */
#define SPAN_PERIOD_FRACTION OKID_R(0.9)

static okid_real ratio_or_inf(okid_real largest, okid_real smallest)
{
    return smallest > 0 ? largest / smallest : (okid_real)INFINITY;
}

/* Singular values of the equilibrated leading cols x cols block of R11 into diag_s (decreasing). */
static okid_status equilibrated_singular_values(okid_identifier *id, int cols)
{
    okid_views_ *v = &id->at_;
    okid_lsq_equilibrated_copy(v->r, id->dims_.w, cols, v->diag_scale, v->diag_a);
    return okid_la_svd(cols, cols, v->diag_a, cols, v->diag_s, v->diag_vt, cols, v->diag_work);
}

okid_status okid_diagnose_regressor(okid_identifier *id, int n, int regressor_rank, okid_regressor_diagnostics *out,
                                    unsigned *warnings)
{
    const okid_dims_ *d = &id->dims_;
    const int q = d->q, nu = d->r * (d->p + 1);
    const okid_real *s = id->at_.diag_s;
    const okid_real gap = okid_sqrt(id->rank_tolerance_);
    okid_lsq_column_norms(id->at_.r, d->w, q, id->at_.diag_scale);

    okid_status st = equilibrated_singular_values(id, nu);
    if (st != OKID_OK) {
        return st;
    }
    out->input_condition = ratio_or_inf(s[0], s[nu - 1]);
    if (out->input_condition * gap > 1) {
        *warnings |= OKID_W_WEAK_EXCITATION;
    }

    st = equilibrated_singular_values(id, q);
    if (st != OKID_OK) {
        return st;
    }
    out->lsq_condition = ratio_or_inf(s[0], s[q - 1]);
    const int model_rank = nu + n;
    out->expected_rank = model_rank < q ? model_rank : q;
    if (regressor_rank < out->expected_rank) {
        *warnings |= OKID_W_RANK_BELOW_MODEL;
    }
    /* Noise lifts every singular value past the model's r (p + 1) + n; (near) noise-free data leaves a gap. */
    if (model_rank < q && s[model_rank] <= gap * s[0]) {
        *warnings |= OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM;
    }
    return OKID_OK;
}

void okid_diagnose_realization(const okid_identifier *id, int n, const okid_mode *modes, int num_modes,
                               okid_real *condition, unsigned *warnings)
{
    const okid_real *sv = id->at_.sv;
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
    const okid_real span = (okid_real)(id->cfg_.hankel_rows + id->cfg_.hankel_cols) * id->cfg_.dt;
    if (slowest > 0 && span * slowest < SPAN_PERIOD_FRACTION) {
        *warnings |= OKID_W_HANKEL_SPAN_SHORT;
    }
}
