/* SPDX-License-Identifier: Apache-2.0 */
/* The physical modes over the observer orders and Hankel windows of the choice: identify, table, select, combine. */
#include "auto_modes.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>


/* The selection of table with criteria, in a workspace of bytes of its own (*workspace, freed by auto_modes_free). */
static okid_status select_into(const okid_stabilization *table, int m, const okid_mode_selection_criteria *criteria,
                               size_t bytes, void **workspace, okid_mode_selection *selection)
{
    if ((*workspace = mode_windows_workspace(bytes)) == NULL) return OKID_E_WORKSPACE_TOO_SMALL;
    return okid_select_modes(table, m, criteria, *workspace, bytes, selection, NULL);
}

/* window > 0: alpha = beta = window; 0 keeps cfg's Hankel size (given by the user). */
static okid_status run_window(auto_run *run, const okid_config *cfg, int window, int max_order, size_t n,
                              const okid_real *u, const okid_real *y, const okid_mode_selection_criteria *criteria)
{
    run->cfg = *cfg;
    if (window > 0) run->cfg.hankel_rows = run->cfg.hankel_cols = window;
    run->cfg.order = 0;
    size_t bytes = 0;
    okid_status st = okid_workspace_size(&run->cfg, &bytes);
    if (st != OKID_OK) return st;
    if ((run->workspace = mode_windows_workspace(bytes)) == NULL) return OKID_E_WORKSPACE_TOO_SMALL;
    st = okid_init(&run->id, &run->cfg, run->workspace, bytes, NULL);
    if (st == OKID_OK) {
        st = okid_push_block(&run->id, n, u, (size_t)cfg->num_inputs, y, (size_t)cfg->num_outputs, NULL);
    }
    if (st == OKID_OK) st = okid_identify(&run->id, &run->result);
    int top = max_order < run->result.num_singular_values ? max_order : run->result.num_singular_values;
    top -= top % 2;
    if (st == OKID_OK && top < 2) st = OKID_E_BAD_ORDER;
    if (st == OKID_OK) st = okid_stabilization_workspace_size(&run->id, top, 2, &bytes);
    if (st == OKID_OK && (run->table_workspace = mode_windows_workspace(bytes)) == NULL) st = OKID_E_WORKSPACE_TOO_SMALL;
    if (st == OKID_OK) st = okid_stabilization_compute(&run->id, top, 2, NULL, run->table_workspace, bytes, &run->table);
    if (st == OKID_OK) st = okid_mode_selection_workspace_size(top, 2, &bytes);
    if (st == OKID_OK) st = select_into(&run->table, cfg->num_outputs, criteria, bytes, &run->selection_workspace, &run->selection);
    /* without EMAC: a heavily damped mode decays below the noise within a long window, and its
       EMAC there (the last block row of the observability matrix) compares noise */
    okid_mode_selection_criteria unchecked = *criteria;
    unchecked.emac_min = 0;
    if (st == OKID_OK) st = select_into(&run->table, cfg->num_outputs, &unchecked, bytes, &run->unchecked_workspace, &run->unchecked);
    if (st == OKID_OK) {
        const okid_real *sv = run->result.singular_values;
        run->noise_floor = run->result.num_singular_values > top && sv[0] > 0 ? (double)(sv[top] / sv[0]) : 0;
    }
    return st;
}

/* One observer order's windows: their modes, each held by every window (one window: its own). */
static void combine_windows(auto_observer *ob, int num_runs, const okid_mode_selection_criteria *criteria, int m)
{
    /* group the windows' modes: a mode of window w joins the first reported mode it matches */
    int support[OKID_MAX_ORDER] = {0};
    for (int w = 0; w < num_runs; ++w) {
        if (ob->runs[w].status == OKID_OK) {
            mode_windows_add(criteria, &ob->runs[w].selection, w, m, ob->modes, &ob->num_modes, support);
        }
    }
    /* a window whose span outlasts a mode (its amplitude decays below the Hankel matrix's noise share
       over the window, |lambda|^(alpha - 1) < sigma_(top + 1) / sigma_1) cannot check its EMAC: there
       the mode counts when it is stable across orders without the EMAC criterion */
    for (int w = 0; w < num_runs; ++w) {
        const auto_run *run = &ob->runs[w];
        if (run->status != OKID_OK) continue;
        for (int k = 0; k < run->unchecked.num_modes; ++k) {
            const okid_selected_mode *s = &run->unchecked.modes[k];
            const double magnitude = hypot((double)s->mode.eigenvalue.re, (double)s->mode.eigenvalue.im);
            if (!(pow(magnitude, run->cfg.hankel_rows - 1) < run->noise_floor)) continue;
            for (int g = 0; g < ob->num_modes; ++g) {
                if (!(support[g] & (1 << w)) && mode_windows_same(criteria, &ob->modes[g].selected->mode, &s->mode, m)) {
                    support[g] |= 1 << w, ++ob->modes[g].windows;
                    break;
                }
            }
        }
    }
    /* every window: a physical mode does not move with the window, and a window that outlasts it
       confirms it without EMAC (above); two of three let a mode at the edge of the cluster-size rule
       in two windows through (GWS 261: 1.32 Hz, zeta 0.08, docs/quality.md section 8) */
    mode_windows_keep(ob->modes, &ob->num_modes, num_runs);
}

/* a and b are one resonance: b within a's half-power band (|f_a - f_b| <= zeta_a f_a), shapes alike */
static int one_resonance(const okid_mode_selection_criteria *c, const okid_mode *a, const okid_mode *b, int m)
{
    const double fa = (double)a->frequency_hz;
    return fabs(fa - (double)b->frequency_hz) <= (double)a->damping_ratio * fa &&
           (double)okid_mac(a->sensor_shape, b->sensor_shape, m) >= (double)c->mac_min;
}

/*
 * The observer orders' modes: each observer order's modes (by increasing frequency) join, in order
 * of frequency, the group whose last member is the same mode within AUTO_OBSERVER_DISTANCE (a chain:
 * a mode drifts with the observer's span) and holds no mode of that observer order yet. The modes
 * of the first observer order (the rule of before) stay: a group of one that most observer orders
 * hold is represented by its member of median frequency, another by the first's own member, unless
 * it is one resonance with a mode most hold (the same peak fitted with another damping), or its own
 * EMAC or MPC is below AUTO_UNCONFIRMED_MIN (nothing then confirms it). A group
 * without the first observer order's mode is a physical mode only when all the other observer orders
 * but one hold it: the first is the measured best single span (docs/quality.md section 8, rule 3),
 * and three of five let modes no other route confirms through (GWS 261: 1.271 Hz).
 */
static void combine_observers(auto_modes *out, int m)
{
    static const int none = -1;
    auto_mode *all = out->pool.all;
    int *group_of = out->pool.group_of, *last = out->pool.last, *held = out->pool.held, *size = out->pool.size;
    int *chosen = out->pool.chosen, *most = out->pool.most;
    int count = 0;
    for (int j = 0; j < out->num_observers; ++j) {
        const auto_observer *ob = &out->observers[j];
        if (ob->runs[0].status != OKID_OK) continue;
        for (int k = 0; k < ob->num_modes; ++k) {
            auto_mode md = ob->modes[k];
            md.observer = j;
            int i = count++;
            while (i > 0 && all[i - 1].selected->mode.frequency_hz > md.selected->mode.frequency_hz) {
                all[i] = all[i - 1];
                --i;
            }
            all[i] = md;
        }
    }
    okid_mode_selection_criteria across = out->criteria;
    across.frequency_distance = (okid_real)AUTO_OBSERVER_DISTANCE;
    int groups = 0;
    for (int i = 0; i < count; ++i) {
        group_of[i] = none;
        for (int g = groups - 1; g >= 0 && group_of[i] == none; --g) {
            if (!(held[g] & (1 << all[i].observer)) && mode_windows_same(&across, &all[last[g]].selected->mode,
                                                                         &all[i].selected->mode, m)) {
                group_of[i] = g;
            }
        }
        if (group_of[i] == none) {
            group_of[i] = groups, held[groups] = 0, size[groups] = 0, ++groups;
        }
        const int g = group_of[i];
        last[g] = i, held[g] |= 1 << all[i].observer, ++size[g];
    }
    /* the representatives: the median member of a group most hold, the first observer's member of
       another (kept unless one resonance with a group most hold); a group without the first observer
       order's mode only when all the others but one hold it */
    for (int g = 0; g < groups; ++g) {
        const int with_first = held[g] & 1;
        most[g] = 2 * size[g] > out->valid_observers && (with_first || size[g] >= out->valid_observers - 1);
        chosen[g] = none;
        int median = (size[g] - 1) / 2;
        for (int i = 0; i < count && chosen[g] == none && (most[g] || with_first); ++i) {
            if (group_of[i] == g && (most[g] ? median-- == 0 : all[i].observer == 0)) chosen[g] = i;
        }
    }
    out->num_modes = 0;
    for (int g = 0; g < groups && out->num_modes < OKID_MAX_ORDER; ++g) {
        if (chosen[g] == none) continue;
        int shared = 0;
        for (int h = 0; h < groups && !most[g] && !shared; ++h) {
            shared = most[h] && one_resonance(&out->criteria, &all[chosen[g]].selected->mode,
                                              &all[chosen[h]].selected->mode, m);
        }
        if (shared) continue;
        const okid_mode *alone = &all[chosen[g]].selected->mode;
        const okid_real least = (okid_real)AUTO_UNCONFIRMED_MIN;
        if (!most[g] && !(alone->emac >= least && alone->mpc >= least)) {
            continue; /* most observer orders do not confirm it, nor do its own indicators */
        }
        auto_mode md = all[chosen[g]];
        md.observers = size[g];
        out->modes[out->num_modes++] = md;
    }
}

/* The observer orders' runs, shared by the threads that take them in turn. */
typedef struct observer_jobs {
    auto_modes *out;
    const auto_choice *choice;
    const okid_config *cfg;
    size_t n;
    const okid_real *u, *y;
    int next;
    pthread_mutex_t lock;
} observer_jobs;

/* Observer order j's windows, into out->observers[j] (nothing else is written: the runs are independent). */
static void run_observer(observer_jobs *jobs, int j)
{
    const auto_choice *choice = jobs->choice;
    auto_modes *out = jobs->out;
    okid_config cfg = *jobs->cfg;
    cfg.observer_order = choice->observer_orders[j];
    const int max_order = choice->max_orders[j];
    auto_observer *ob = &out->observers[j];
    for (int w = 0; w < out->num_runs; ++w) {
        const int window = (choice->given & AUTO_GIVEN_HANKEL) ? 0 : choice->windows[w];
        ob->runs[w].status = run_window(&ob->runs[w], &cfg, window, max_order, jobs->n, jobs->u, jobs->y, &out->criteria);
    }
}

static void *observer_worker(void *arg)
{
    observer_jobs *jobs = arg;
    for (;;) {
        pthread_mutex_lock(&jobs->lock);
        const int j = jobs->next++;
        pthread_mutex_unlock(&jobs->lock);
        if (j >= jobs->out->num_observers) return NULL;
        run_observer(jobs, j);
    }
}

/*
 * Every observer order's runs, on up to one thread per core (they share nothing but the record
 * and the criteria, which they only read; the results do not depend on which thread ran what).
 * A thread that cannot be started leaves its share to the others, this one included.
 */
static void run_observers(observer_jobs *jobs)
{
    enum { MOST_THREADS = AUTO_OBSERVERS - 1 };
    pthread_t threads[MOST_THREADS];
    const long cores = sysconf(_SC_NPROCESSORS_ONLN);
    int extra = (cores > 1 ? (int)cores : 1) - 1, started = 0;
    if (extra > jobs->out->num_observers - 1) extra = jobs->out->num_observers - 1;
    if (extra > MOST_THREADS) extra = MOST_THREADS;
    while (started < extra && pthread_create(&threads[started], NULL, observer_worker, jobs) == 0) ++started;
    observer_worker(jobs);
    for (int t = 0; t < started; ++t) pthread_join(threads[t], NULL);
    pthread_mutex_destroy(&jobs->lock);
}

okid_status auto_modes_find(const auto_choice *choice, const okid_config *cfg, size_t n, const okid_real *u,
                            const okid_real *y, auto_modes *out)
{
    memset(out, 0, sizeof *out);
    okid_mode_selection_criteria_default(&out->criteria);
    out->criteria.frequency_min_hz = (okid_real)choice->frequency_min_hz;
    out->criteria.frequency_max_hz = (okid_real)choice->frequency_max_hz;
    /* a mode damped up to 1/sqrt(2) still has a resonance peak in the frequency response; the
       selection's 0.2 is the rule of thumb for structures, and the paper's plant is damped 33 % */
    out->criteria.damping_max = (okid_real)AUTO_DAMPING_MAX;
    out->num_runs = choice->num_windows;
    out->num_observers = choice->num_observers; /* at least 1: auto_choose() */
    observer_jobs jobs = {out, choice, cfg, n, u, y, 0, PTHREAD_MUTEX_INITIALIZER};
    run_observers(&jobs);
    const int m = cfg->num_outputs;
    if (out->observers[0].runs[0].status != OKID_OK) return out->observers[0].runs[0].status;
    for (int j = 0; j < out->num_observers; ++j) {
        if (out->observers[j].runs[0].status != OKID_OK) continue; /* a longer observer the record cannot hold */
        ++out->valid_observers;
        combine_windows(&out->observers[j], out->num_runs, &out->criteria, m);
    }
    combine_observers(out, m);
    /* the model: the shortest observer order whose main table has an order holding every mode, else
       the first observer order's order holding the most */
    int found = 0;
    for (int j = 0; j < out->num_observers && !found; ++j) {
        if (out->observers[j].runs[0].status != OKID_OK) continue;
        mode_windows_order(&out->observers[j].runs[0].table, &out->criteria, out->modes, out->num_modes, m, &out->order,
                           &out->order_holds_all);
        if (out->order_holds_all) out->observer = j, found = 1;
    }
    if (!found) {
        out->observer = 0;
        mode_windows_order(&out->observers[0].runs[0].table, &out->criteria, out->modes, out->num_modes, m, &out->order,
                           &out->order_holds_all);
    }
    return OKID_OK;
}

const auto_run *auto_main_run(const auto_modes *am)
{
    return &am->observers[am->observer].runs[0];
}

const char *auto_pole_verdict(const auto_modes *am, const okid_mode *pole, int m)
{
    return mode_windows_verdict(&am->criteria, am->modes, am->num_modes, pole, m, AUTO_UNSTABLE_ACROSS);
}

void auto_modes_free(auto_modes *am)
{
    for (int j = 0; j < am->num_observers; ++j) {
        for (int w = 0; w < am->num_runs; ++w) {
            auto_run *run = &am->observers[j].runs[w];
            free(run->workspace);
            free(run->table_workspace);
            free(run->selection_workspace);
            free(run->unchecked_workspace);
        }
    }
    memset(am, 0, sizeof *am);
}
