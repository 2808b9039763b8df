/*
 * Host-side plant simulator for `pdtfit autotune-sim`: the process
 *
 *   G(s) = K prod_j (Z_j s + 1) / prod_i (T_i s + 1) e^{-D s}
 *
 * driven by an output held constant over each scan (zero-order hold) and
 * read once per scan, before the new output is applied.
 *
 * The rational part is realised as a cascade of first-order sections, lag i
 * paired with zero i while zeros remain: (Z s + 1) / (T s + 1) =
 * Z / T + (1 - Z / T) / (T s + 1). The state equation x' = A x + B v is
 * integrated exactly over a constant input by the matrix exponential of
 * [[A h, B h], [0, 0]] (scaling and squaring of a Taylor series), so the
 * result does not depend on the scan period being small against the lags.
 * The dead time D = (l + f) Ts puts at most one switch of the delayed input
 * inside a scan, at f Ts: each scan is integrated as two exact pieces.
 *
 * Everything is double, whatever the library's real type. Memory comes from
 * malloc; this file is included by the command line only (one translation
 * unit), hence its static functions.
 */
#ifndef PDTFIT_PLANT_SIM_H
#define PDTFIT_PLANT_SIM_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct plant_sim {
    size_t n;     /* states (lags) */
    double *Phi1; /* n x n and n: the exact step over the first piece */
    double *Gam1;
    double *Phi2; /* ... and over the second (f > 0 only) */
    double *Gam2;
    double *C;  /* output row */
    double Dff; /* direct feedthrough (as many zeros as lags) */
    double *x;  /* state, deviation from rest */
    double *tmp;
    size_t l;     /* whole scans of dead time */
    double f;     /* fraction of a scan, 0 <= f < 1 */
    double *hist; /* outputs applied, ring of l + 2 deviations */
    size_t hist_len;
    uint64_t scans; /* scans advanced */
    double u0, y0;  /* operating point */
} plant_sim_t;

/* exp(M) of an m x m matrix (row-major), into E; W is 3 m^2 scratch. */
static void plant_expm(const double *M, size_t m, double *E, double *W)
{
    double norm = 0.0;
    for (size_t j = 0; j < m; j++) {
        double col = 0.0;
        for (size_t i = 0; i < m; i++) col += fabs(M[i * m + j]);
        if (col > norm) norm = col;
    }
    int s = 0;
    while (norm > 0.25 && s < 1000) {
        norm *= 0.5;
        s++;
    }
    const double scale = ldexp(1.0, -s);
    double *term = W, *next = W + m * m, *sq = W + 2 * m * m;
    /* E = I + X + X^2/2! + ..., X = M / 2^s with ||X||_1 <= 1/4: 24 terms
     * leave less than 1e-30. */
    for (size_t i = 0; i < m * m; i++) {
        E[i] = 0.0;
        term[i] = 0.0;
    }
    for (size_t i = 0; i < m; i++) {
        E[i * m + i] = 1.0;
        term[i * m + i] = 1.0;
    }
    for (int k = 1; k <= 24; k++) {
        for (size_t i = 0; i < m; i++)
            for (size_t j = 0; j < m; j++) {
                double acc = 0.0;
                for (size_t p = 0; p < m; p++) acc += term[i * m + p] * M[p * m + j];
                next[i * m + j] = acc * scale / (double)k;
            }
        memcpy(term, next, m * m * sizeof *term);
        for (size_t i = 0; i < m * m; i++) E[i] += term[i];
    }
    for (int r = 0; r < s; r++) {
        for (size_t i = 0; i < m; i++)
            for (size_t j = 0; j < m; j++) {
                double acc = 0.0;
                for (size_t p = 0; p < m; p++) acc += E[i * m + p] * E[p * m + j];
                sq[i * m + j] = acc;
            }
        memcpy(E, sq, m * m * sizeof *E);
    }
}

/* Phi = e^{A h}, Gam = int_0^h e^{A s} ds B. */
static int plant_discretize(const double *A, const double *B, size_t n, double h, double *Phi,
                            double *Gam)
{
    const size_t m = n + 1;
    double *M = calloc(m * m, sizeof *M);
    double *E = malloc(m * m * sizeof *E);
    double *W = malloc(3 * m * m * sizeof *W);
    if (!M || !E || !W) {
        free(M);
        free(E);
        free(W);
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) M[i * m + j] = A[i * n + j] * h;
        M[i * m + n] = B[i] * h;
    }
    plant_expm(M, m, E, W);
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) Phi[i * n + j] = E[i * m + j];
        Gam[i] = E[i * m + n];
    }
    free(M);
    free(E);
    free(W);
    return 0;
}

static void plant_free(plant_sim_t *p)
{
    free(p->Phi1);
    free(p->Gam1);
    free(p->Phi2);
    free(p->Gam2);
    free(p->C);
    free(p->x);
    free(p->tmp);
    free(p->hist);
    memset(p, 0, sizeof *p);
}

/* Prepares p at rest: output y0 with the input held at u0. Lags > 0,
 * zeros != 0, n_zeros <= n_lags, n_lags >= 1, delay >= 0, Ts > 0 (the
 * caller checks). Returns 0, or -1 when out of memory. */
static int plant_init(plant_sim_t *p, double K, const double *lags, size_t n_lags,
                      const double *zeros, size_t n_zeros, double delay, double Ts, double u0,
                      double y0)
{
    memset(p, 0, sizeof *p);
    const size_t n = n_lags;
    p->n = n;
    p->u0 = u0;
    p->y0 = y0;
    double *A = calloc(n * n, sizeof *A);
    double *B = calloc(n, sizeof *B);
    /* v = vx . x + vu u: the input of the section being built. */
    double *vx = calloc(n, sizeof *vx);
    double vu = K;
    p->Phi1 = malloc(n * n * sizeof *p->Phi1);
    p->Gam1 = malloc(n * sizeof *p->Gam1);
    p->Phi2 = malloc(n * n * sizeof *p->Phi2);
    p->Gam2 = malloc(n * sizeof *p->Gam2);
    p->C = calloc(n, sizeof *p->C);
    p->x = calloc(n, sizeof *p->x);
    p->tmp = malloc(n * sizeof *p->tmp);
    if (!A || !B || !vx || !p->Phi1 || !p->Gam1 || !p->Phi2 || !p->Gam2 || !p->C || !p->x ||
        !p->tmp) {
        free(A);
        free(B);
        free(vx);
        plant_free(p);
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        const double T = lags[i];
        for (size_t j = 0; j < n; j++) A[i * n + j] = vx[j] / T;
        A[i * n + i] -= 1.0 / T;
        B[i] = vu / T;
        const double c = i < n_zeros ? zeros[i] / T : 0.0;
        for (size_t j = 0; j < n; j++) vx[j] *= c;
        vx[i] += 1.0 - c;
        vu *= c;
    }
    memcpy(p->C, vx, n * sizeof *vx);
    p->Dff = vu;

    double l = floor(delay / Ts + 1e-9);
    double f = delay / Ts - l;
    if (f < 1e-9) f = 0.0;
    if (f > 1.0 - 1e-9) {
        l += 1.0;
        f = 0.0;
    }
    p->l = (size_t)l;
    p->f = f;
    int rc = 0;
    if (f > 0.0) {
        rc |= plant_discretize(A, B, n, f * Ts, p->Phi1, p->Gam1);
        rc |= plant_discretize(A, B, n, (1.0 - f) * Ts, p->Phi2, p->Gam2);
    } else {
        rc |= plant_discretize(A, B, n, Ts, p->Phi1, p->Gam1);
    }
    free(A);
    free(B);
    free(vx);
    p->hist_len = p->l + 2;
    p->hist = calloc(p->hist_len, sizeof *p->hist);
    if (rc != 0 || !p->hist) {
        plant_free(p);
        return -1;
    }
    return 0;
}

/* The output deviation applied j scans before the current one (j >= 1);
 * 0 before the start. */
static double plant_past(const plant_sim_t *p, size_t j)
{
    if (j > p->scans) return 0.0;
    return p->hist[(size_t)((p->scans - j) % p->hist_len)];
}

/* The process value now, at the start of the scan (before the output of
 * this scan is applied). */
static double plant_output(const plant_sim_t *p)
{
    double y = p->y0;
    for (size_t i = 0; i < p->n; i++) y += p->C[i] * p->x[i];
    /* The delayed input just before now: applied l + 1 scans ago when the
     * dead time has a fraction (or is whole and nonzero), this scan's own
     * output never (it is applied after the read). */
    if (p->Dff != 0.0) y += p->Dff * plant_past(p, p->l + 1u);
    return y;
}

static void plant_piece(plant_sim_t *p, const double *Phi, const double *Gam, double v)
{
    const size_t n = p->n;
    for (size_t i = 0; i < n; i++) {
        double acc = Gam[i] * v;
        for (size_t j = 0; j <= i; j++) acc += Phi[i * n + j] * p->x[j];
        p->tmp[i] = acc;
    }
    memcpy(p->x, p->tmp, n * sizeof *p->x);
}

/* Applies the output u over one scan period. */
static void plant_advance(plant_sim_t *p, double u)
{
    p->hist[(size_t)(p->scans % p->hist_len)] = u - p->u0;
    p->scans++;
    /* Over [k Ts, (k + 1) Ts) the process sees u[k - l - 1] until f Ts,
     * then u[k - l]; with the scan just stored as u[k], these are the
     * outputs l + 2 and l + 1 scans back from the new count. */
    if (p->f > 0.0) {
        plant_piece(p, p->Phi1, p->Gam1, plant_past(p, p->l + 2u));
        plant_piece(p, p->Phi2, p->Gam2, plant_past(p, p->l + 1u));
    } else {
        plant_piece(p, p->Phi1, p->Gam1, plant_past(p, p->l + 1u));
    }
}

#endif /* PDTFIT_PLANT_SIM_H */
