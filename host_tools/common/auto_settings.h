/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Settings from the data (okid identify without --decimation, --observer-order or --hankel-*):
 * the band that holds the outputs' energy, from their averaged periodogram, gives the decimation
 * and the slowest period; the slowest period gives the observer's and the Hankel window's spans.
 * docs/quality.md, section 8, has the rules and the measurements behind them.
 */
#ifndef OKID_CLI_AUTO_SETTINGS_H
#define OKID_CLI_AUTO_SETTINGS_H

#include <stddef.h>

#include "okid/okid.h"

/* Which of the settings the user gave (the others are chosen). */
enum {
    AUTO_GIVEN_DECIMATION = 1u << 0,
    AUTO_GIVEN_OBSERVER = 1u << 1,
    AUTO_GIVEN_HANKEL = 1u << 2
};

/* The record's output band: 5 % and 95 % of the outputs' energy (each output normalised to unit energy). */
typedef struct auto_band {
    double low_hz;      /* 5 % of the energy lies below: about the slowest mode */
    double high_hz;     /* 95 % lies below */
    int segment;        /* Welch segment length [samples] */
} auto_band;

/* Observer orders of the mode selection when the observer order is chosen: AUTO_OBSERVERS shares of
   the slowest period, from AUTO_OBSERVER_FIRST by AUTO_OBSERVER_STEP (0.5, 0.6, ..., 0.9 T): a
   physical mode does not move with the observer's span, a fitted one does (docs/quality.md section 8). */
#define AUTO_OBSERVERS 5
#define AUTO_OBSERVER_FIRST 0.5
#define AUTO_OBSERVER_STEP 0.1

/* The choices and their inputs, for the result's "chosen" object and the table's lines. */
typedef struct auto_choice {
    unsigned given;              /* AUTO_GIVEN_* bits */
    int no_band;                 /* 1: the record has no band (too short or flat): the defaults were kept */
    auto_band band;
    double slowest_period_s;     /* 1 / band.low_hz */
    int decimation, observer_order, hankel, hankel_cols;  /* the settings used (given or chosen) */
    int observer_limit;          /* the largest p the record's length allows (ten rows per unknown) */
    int observer_orders[AUTO_OBSERVERS];  /* observer orders of the mode selection, shortest first */
    int num_observers;           /* distinct ones: up to AUTO_OBSERVERS when chosen, else 1 */
    int windows[3];              /* Hankel windows of the mode selection, main one first (2T, 4T checks) */
    int num_windows;             /* 3 when the Hankel size is chosen, else 1 */
    int max_order;               /* largest order of the stabilization tables (the first observer order's) */
    int max_orders[AUTO_OBSERVERS];  /* largest order of each observer order's tables (m p at most) */
    double frequency_min_hz, frequency_max_hz;  /* band of the mode selection */
} auto_choice;

/*
 * The band of the channels y (n samples of m values, row-major; the outputs, or the inputs) at dt: Welch
 * averages (Hann window, half overlap) of each mean-removed channel, each normalised to unit
 * energy and summed. 0, or -1 when the record is too short (fewer than 64 samples) or flat.
 */
int auto_channel_band(const okid_real *y, size_t n, int m, double dt, auto_band *band);

/*
 * The settings: those in `given` are kept from cfg, the others are chosen from the band (rules in
 * docs/quality.md section 8). cfg gets the settings of the main run. n: samples of the record.
 * A band with low_hz <= 0 (auto_channel_band() failed) keeps cfg's settings, the library's defaults.
 */
void auto_choose(okid_config *cfg, unsigned given, size_t n, const auto_band *band, auto_choice *choice);

#endif
