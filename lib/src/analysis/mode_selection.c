/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Automatic selection of physical modes from a stabilization table (okid/mode_selection.h): hard
 * criteria per pole, greedy clustering by decreasing CMI with per-order uniqueness, a cluster-size
 * rule, the median-frequency representative and the cluster's spread. Integer arrays and the
 * result in the caller's workspace; O(T log T + T C) for T poles and C clusters.
 */
#include "okid/mode_selection.h"

#include "numerics/carve.h"
#include "numerics/real_math.h"

okid_status okid_mode_selection_criteria_default(okid_mode_selection_criteria *criteria)
{
    if (criteria == NULL) {
        return OKID_E_NULL_POINTER;
    }
    criteria->damping_min = OKID_R(0.0);
    criteria->damping_max = OKID_R(0.2);
    criteria->frequency_min_hz = OKID_R(0.0);
    criteria->frequency_max_hz = OKID_R(0.0);
    criteria->mpc_min = OKID_R(0.5);
    criteria->emac_min = OKID_R(0.5);
    criteria->frequency_distance = OKID_R(0.02);
    criteria->damping_distance = OKID_R(0.5);
    criteria->mac_min = OKID_R(0.9);
    criteria->min_fraction = OKID_R(0.5);
    return OKID_OK;
}

/* value in [lo, hi] (open ends when the flags say so), finite. */
static int in_range(okid_real value, okid_real lo, int lo_open, okid_real hi, int hi_open)
{
    if (!okid_is_finite(value)) {
        return 0;
    }
    if (lo_open ? !(value > lo) : !(value >= lo)) {
        return 0;
    }
    return hi_open ? value < hi : value <= hi;
}

static okid_status refuse(okid_config_issue *issue, const char *field, okid_real value, okid_real lo, okid_real hi)
{
    if (issue != NULL) {
        issue->field = field;
        issue->value = (double)value;
        issue->min = (double)lo;
        issue->max = (double)hi;
    }
    return OKID_E_BAD_PARAMETER;
}

okid_status okid_mode_selection_criteria_check(const okid_mode_selection_criteria *c, okid_config_issue *issue)
{
    if (c == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (issue != NULL) {
        issue->field = NULL;
        issue->value = issue->min = issue->max = 0.0;
    }
    const okid_real big = OKID_REAL_MAX;
    if (!in_range(c->damping_max, 0, 1, 1, 0)) {
        return refuse(issue, "damping_max", c->damping_max, 0, 1);
    }
    if (!in_range(c->damping_min, 0, 0, c->damping_max, 1)) {
        return refuse(issue, "damping_min", c->damping_min, 0, c->damping_max);
    }
    if (!in_range(c->frequency_min_hz, 0, 0, big, 0)) {
        return refuse(issue, "frequency_min_hz", c->frequency_min_hz, 0, big);
    }
    if (!(c->frequency_max_hz == 0) && !in_range(c->frequency_max_hz, c->frequency_min_hz, 1, big, 0)) {
        return refuse(issue, "frequency_max_hz", c->frequency_max_hz, c->frequency_min_hz, big);
    }
    if (!in_range(c->mpc_min, 0, 0, 1, 0)) {
        return refuse(issue, "mpc_min", c->mpc_min, 0, 1);
    }
    if (!in_range(c->emac_min, 0, 0, 1, 0)) {
        return refuse(issue, "emac_min", c->emac_min, 0, 1);
    }
    if (!in_range(c->frequency_distance, 0, 1, 1, 0)) {
        return refuse(issue, "frequency_distance", c->frequency_distance, 0, 1);
    }
    if (!in_range(c->damping_distance, 0, 1, 1, 0)) {
        return refuse(issue, "damping_distance", c->damping_distance, 0, 1);
    }
    if (!in_range(c->mac_min, 0, 0, 1, 0)) {
        return refuse(issue, "mac_min", c->mac_min, 0, 1);
    }
    if (!in_range(c->min_fraction, 0, 1, 1, 0)) {
        return refuse(issue, "min_fraction", c->min_fraction, 0, 1);
    }
    return OKID_OK;
}

/* Views of the workspace: one layout for the size and the carving. */
typedef struct sel_views {
    int *cluster_of; /* per table pole: its cluster, -1 when none */
    int *order_of;   /* per table pole: index of its order */
    int *cand;       /* candidates, sorted */
    int *seed;       /* per cluster: table index of its seed */
    int *count;      /* per cluster: poles; negated when a duplicate was dropped */
    okid_selected_mode *modes;
} sel_views;

static uint64_t sel_carve(uint64_t total, uint64_t nmax, unsigned char *base, sel_views *v)
{
    okid_carver c = {base, 0};
    v->cluster_of = (int *)okid_carve_bytes(&c, sizeof(int) * total);
    v->order_of = (int *)okid_carve_bytes(&c, sizeof(int) * total);
    v->cand = (int *)okid_carve_bytes(&c, sizeof(int) * total);
    v->seed = (int *)okid_carve_bytes(&c, sizeof(int) * total);
    v->count = (int *)okid_carve_bytes(&c, sizeof(int) * total);
    v->modes = (okid_selected_mode *)okid_carve_bytes(&c, sizeof(okid_selected_mode) * nmax);
    return c.used;
}

okid_status okid_mode_selection_workspace_size(int max_order, int step, size_t *bytes)
{
    if (bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (max_order < 1 || max_order > OKID_MAX_ORDER) {
        return OKID_E_BAD_ORDER;
    }
    if (step < 1 || step > max_order) {
        return OKID_E_BAD_SIZE;
    }
    sel_views dry;
    return okid_carve_size(sel_carve(OKID__STAB_MODES(max_order, step), (uint64_t)max_order, NULL, &dry), bytes);
}

static int passes_hard(const okid_mode *md, const okid_mode_selection_criteria *c)
{
    const okid_real mag2 = md->eigenvalue.re * md->eigenvalue.re + md->eigenvalue.im * md->eigenvalue.im;
    if (!md->is_pair || !(mag2 < 1)) {
        return 0;
    }
    if (!(md->damping_ratio > c->damping_min) || !(md->damping_ratio <= c->damping_max)) {
        return 0;
    }
    if (!(md->frequency_hz >= c->frequency_min_hz) || !(md->frequency_hz > 0)) {
        return 0;
    }
    if (c->frequency_max_hz > 0 && !(md->frequency_hz <= c->frequency_max_hz)) {
        return 0;
    }
    return md->mpc >= c->mpc_min && md->emac >= c->emac_min;
}

/* a before b in the clustering order: higher CMI, then higher order, then lower table index. */
static int before(const okid_mode *modes, const int *order_of, int a, int b)
{
    if (modes[a].cmi != modes[b].cmi) {
        return modes[a].cmi > modes[b].cmi;
    }
    if (order_of[a] != order_of[b]) {
        return order_of[a] > order_of[b];
    }
    return a < b;
}

/* Heap sort of idx[0..n-1] by before() (no memory, deterministic). */
static void sift_down(int *idx, int start, int end, const okid_mode *modes, const int *order_of)
{
    int root = start;
    while (2 * root + 1 <= end) {
        int child = 2 * root + 1, swap = root;
        /* max-heap on "after": the element that comes last rises, so the array ends up in order */
        if (before(modes, order_of, idx[swap], idx[child])) {
            swap = child;
        }
        if (child + 1 <= end && before(modes, order_of, idx[swap], idx[child + 1])) {
            swap = child + 1;
        }
        if (swap == root) {
            return;
        }
        const int t = idx[root];
        idx[root] = idx[swap];
        idx[swap] = t;
        root = swap;
    }
}

static void sort_candidates(int *idx, int n, const okid_mode *modes, const int *order_of)
{
    for (int start = (n - 2) / 2; start >= 0; --start) {
        sift_down(idx, start, n - 1, modes, order_of);
    }
    for (int end = n - 1; end > 0; --end) {
        const int t = idx[0];
        idx[0] = idx[end];
        idx[end] = t;
        sift_down(idx, 0, end - 1, modes, order_of);
    }
}

/* Pole a within the clustering gates of pole s (the seed); its distance in *d. */
static int within_gates(const okid_mode *a, const okid_mode *s, int m, const okid_mode_selection_criteria *c,
                        okid_real *d)
{
    const okid_real df = okid_fabs(a->frequency_hz - s->frequency_hz);
    if (!(df <= c->frequency_distance * s->frequency_hz)) {
        return 0;
    }
    const okid_real zmax = a->damping_ratio > s->damping_ratio ? a->damping_ratio : s->damping_ratio;
    if (!(okid_fabs(a->damping_ratio - s->damping_ratio) <= c->damping_distance * zmax)) {
        return 0;
    }
    const okid_real mac = okid_mac(a->sensor_shape, s->sensor_shape, m);
    if (!(mac >= c->mac_min)) {
        return 0;
    }
    *d = df / s->frequency_hz + (1 - mac);
    return 1;
}

/* Cluster k has a pole in order index o (scan the order's block of the table). */
static int has_order(const okid_stabilization *t, const sel_views *v, int k, int o)
{
    const okid_stabilization_order *ord = &t->orders[o];
    for (int i = 0; i < ord->num_modes; ++i) {
        if (v->cluster_of[ord->first + i] == k) {
            return 1;
        }
    }
    return 0;
}

/* Statistics and representative of cluster k over the table's T poles; exact_last_order: the pole
   of the table's last order, when the cluster has one, is the representative (the exact model's). */
static void summarize(const okid_stabilization *t, int total, const sel_views *v, int k, int exact_last_order,
                      okid_selected_mode *out)
{
    const okid_mode *modes = t->modes;
    int n = 0, lo = 0, hi = 0;
    okid_real f0 = modes[v->seed[k]].frequency_hz, z0 = modes[v->seed[k]].damping_ratio;
    okid_real sf = 0, sff = 0, sz = 0, szz = 0, fmin = f0, fmax = f0, zmin = z0, zmax = z0, cmin = 1;
    for (int i = 0; i < total; ++i) {
        if (v->cluster_of[i] != k) {
            continue;
        }
        const okid_real f = modes[i].frequency_hz - f0, z = modes[i].damping_ratio - z0; /* shifted: no cancellation */
        sf += f;
        sff += f * f;
        sz += z;
        szz += z * z;
        fmin = modes[i].frequency_hz < fmin ? modes[i].frequency_hz : fmin;
        fmax = modes[i].frequency_hz > fmax ? modes[i].frequency_hz : fmax;
        zmin = modes[i].damping_ratio < zmin ? modes[i].damping_ratio : zmin;
        zmax = modes[i].damping_ratio > zmax ? modes[i].damping_ratio : zmax;
        cmin = modes[i].cmi < cmin ? modes[i].cmi : cmin;
        const int order = t->orders[v->order_of[i]].order;
        lo = (n == 0 || order < lo) ? order : lo;
        hi = (n == 0 || order > hi) ? order : hi;
        ++n;
    }
    const okid_real inv = OKID_R(1.0) / (okid_real)n;
    const okid_real mf = sf * inv, mz = sz * inv;
    const okid_real vf = sff * inv - mf * mf, vz = szz * inv - mz * mz;
    /* noise-free data: the cluster's pole of the table's last order, the exact model's, when it has one */
    int rep = -1;
    const okid_stabilization_order *last = &t->orders[t->num_orders - 1];
    for (int i = 0; exact_last_order && i < last->num_modes; ++i) {
        if (v->cluster_of[last->first + i] == k) rep = last->first + i;
    }
    if (rep < 0) {
        /* the lower median: the pole with (n - 1) / 2 poles of lower frequency (ties by table index);
           members gathered in the candidate list, free once the clustering is done */
        int *members = v->cand;
        int count = 0;
        for (int i = 0; i < total; ++i) {
            if (v->cluster_of[i] == k) {
                members[count++] = i;
            }
        }
        rep = v->seed[k];
        for (int a = 0; a < count; ++a) {
            const int i = members[a];
            int below = 0;
            for (int b = 0; b < count; ++b) {
                const int j = members[b];
                below += (modes[j].frequency_hz < modes[i].frequency_hz ||
                          (modes[j].frequency_hz == modes[i].frequency_hz && j < i));
            }
            if (below == (n - 1) / 2) {
                rep = i;
                break;
            }
        }
    }
    out->mode = modes[rep];
    out->order = t->orders[v->order_of[rep]].order;
    out->num_orders = n;
    out->lowest_order = lo;
    out->highest_order = hi;
    out->frequency_mean = f0 + mf;
    out->frequency_std = vf > 0 ? okid_sqrt(vf) : 0;
    out->frequency_min = fmin;
    out->frequency_max = fmax;
    out->damping_mean = z0 + mz;
    out->damping_std = vz > 0 ? okid_sqrt(vz) : 0;
    out->damping_min = zmin;
    out->damping_max = zmax;
    out->cmi_min = cmin;
}

okid_status okid_select_modes(const okid_stabilization *table, int num_outputs,
                              const okid_mode_selection_criteria *criteria, void *workspace, size_t bytes,
                              okid_mode_selection *out, okid_config_issue *issue)
{
    if (table == NULL || workspace == NULL || out == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (num_outputs < 1 || num_outputs > OKID_MAX_DIMENSION || table->num_orders < 0) {
        return OKID_E_BAD_SIZE;
    }
    if (table->num_orders > 0 && (table->orders == NULL || table->modes == NULL)) {
        return OKID_E_NULL_POINTER;
    }
    okid_mode_selection_criteria crit;
    (void)okid_mode_selection_criteria_default(&crit);
    if (criteria != NULL) {
        const okid_status st = okid_mode_selection_criteria_check(criteria, issue);
        if (st != OKID_OK) {
            return st;
        }
        crit = *criteria;
    } else if (issue != NULL) {
        issue->field = NULL;
        issue->value = issue->min = issue->max = 0.0;
    }
    if (((size_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    /* the table's size: its poles and its largest order; each order's block must follow the last */
    int total = 0, nmax = 0;
    for (int o = 0; o < table->num_orders; ++o) {
        const okid_stabilization_order *ord = &table->orders[o];
        if (ord->num_modes < 0 || ord->order < 1 || ord->order > OKID_MAX_ORDER || ord->first != total ||
            ord->num_modes > ord->order) {
            return OKID_E_BAD_SIZE;
        }
        total += ord->num_modes;
        nmax = ord->order > nmax ? ord->order : nmax;
    }
    sel_views v;
    const uint64_t needed = sel_carve((uint64_t)total, (uint64_t)nmax, NULL, &v);
    if ((uint64_t)bytes < needed) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    (void)sel_carve((uint64_t)total, (uint64_t)nmax, (unsigned char *)workspace, &v);
    const okid_mode *modes = table->modes;
    const int m = num_outputs, K = table->num_orders;

    /* 1. hard criteria */
    int num_cand = 0;
    for (int o = 0; o < K; ++o) {
        const okid_stabilization_order *ord = &table->orders[o];
        for (int i = ord->first; i < ord->first + ord->num_modes; ++i) {
            v.order_of[i] = o;
            v.cluster_of[i] = -1;
            if (passes_hard(&modes[i], &crit)) {
                v.cand[num_cand++] = i;
            }
        }
    }
    sort_candidates(v.cand, num_cand, modes, v.order_of);

    /* 2. greedy clustering: nearest admissible seed, one pole per order */
    int num_clusters = 0;
    for (int ci = 0; ci < num_cand; ++ci) {
        const int i = v.cand[ci];
        int best = -1;
        okid_real best_d = 0;
        for (int k = 0; k < num_clusters; ++k) {
            okid_real d = 0;
            if (within_gates(&modes[i], &modes[v.seed[k]], m, &crit, &d) && (best < 0 || d < best_d) &&
                !has_order(table, &v, k, v.order_of[i])) {
                best = k;
                best_d = d;
            }
        }
        if (best < 0) {
            best = num_clusters++;
            v.seed[best] = i;
            v.count[best] = 0;
        }
        v.cluster_of[i] = best;
        ++v.count[best];
    }

    /* 3. physical clusters: in at least min_orders orders; of two with seeds within each other's
       gates, the one in more orders (then the earlier seed) stays */
    okid_real need = crit.min_fraction * (okid_real)K;
    int min_orders = (int)need;
    if ((okid_real)min_orders < need) {
        ++min_orders;
    }
    min_orders = min_orders < 2 ? 2 : min_orders;
    /* noise-free data: a table cut at the Hankel matrix's numerical rank ends at the exact model,
       and no higher order is there to confirm its poles (the orders beyond hold only round-off);
       a cluster with a pole of that last order counts as confirmed */
    const int step = K > 1 ? table->orders[1].order - table->orders[0].order : K == 1 ? table->orders[0].order : 0;
    const int exact_last_order = K > 0 && table->noise_free && table->rank_limit < table->orders[K - 1].order + step;
    if (exact_last_order) {
        for (int k = 0; k < num_clusters; ++k) {
            if (v.count[k] < min_orders && has_order(table, &v, k, K - 1)) {
                v.count[k] = min_orders;
            }
        }
    }
    int dropped = 0;
    for (int k = 0; k < num_clusters; ++k) {
        if (v.count[k] < min_orders) {
            continue;
        }
        for (int j = 0; j < num_clusters; ++j) {
            okid_real d = 0;
            if (j != k && v.count[j] >= min_orders &&
                (v.count[j] > v.count[k] || (v.count[j] == v.count[k] && j < k)) &&
                within_gates(&modes[v.seed[k]], &modes[v.seed[j]], m, &crit, &d)) {
                v.count[k] = -v.count[k]; /* a duplicate of j */
                ++dropped;
                break;
            }
        }
    }
    /* room for nmax modes: when more qualify (min_fraction < 0.5 only), keep those in the most orders */
    int num_sel = 0;
    for (int k = 0; k < num_clusters; ++k) {
        if (v.count[k] >= min_orders) {
            ++num_sel;
        }
    }
    int threshold = min_orders;
    while (num_sel > nmax) {
        int at = 0;
        for (int k = 0; k < num_clusters; ++k) {
            at += (v.count[k] == threshold);
        }
        num_sel -= at;
        dropped += at;
        ++threshold;
    }
    /* 4. representatives, by increasing frequency (insertion: at most nmax of them) */
    int written = 0;
    for (int k = 0; k < num_clusters; ++k) {
        if (v.count[k] < threshold) {
            continue;
        }
        okid_selected_mode sm;
        summarize(table, total, &v, k, exact_last_order, &sm);
        int pos = written;
        while (pos > 0 && v.modes[pos - 1].mode.frequency_hz > sm.mode.frequency_hz) {
            v.modes[pos] = v.modes[pos - 1];
            --pos;
        }
        v.modes[pos] = sm;
        ++written;
    }
    out->num_modes = written;
    out->modes = v.modes;
    out->num_orders = K;
    out->min_orders = min_orders;
    out->num_candidates = num_cand;
    out->num_clusters = num_clusters;
    out->num_dropped = dropped;
    out->exact_last_order = exact_last_order;
    return OKID_OK;
}
