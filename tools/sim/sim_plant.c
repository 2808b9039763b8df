#include "sim_plant.h"

#include <math.h>
#include <string.h>

#define NMAX SIM_PLANT_MAX_STATES
#define MMAX (SIM_PLANT_MAX_STATES + 1u)

/* The series realisation under construction: the signal between sections
 * is v = vx . x + vu u, starting as K u. */
typedef struct build {
    size_t n;
    double A[NMAX * NMAX];
    double B[NMAX];
    double vx[NMAX];
    double vu;
} build_t;

/* Appends a section x_s' = As x_s + Bs v, v' = Cs x_s + Ds v with ns states. */
static int add_section(build_t *b, size_t ns, const double *As, const double *Bs, const double *Cs,
                       double Ds)
{
    if (b->n + ns > NMAX) {
        return -1;
    }
    const size_t n0 = b->n;
    for (size_t i = 0; i < ns; i++) {
        for (size_t j = 0; j < n0; j++) {
            b->A[(n0 + i) * NMAX + j] = Bs[i] * b->vx[j];
        }
        for (size_t j = 0; j < ns; j++) {
            b->A[(n0 + i) * NMAX + n0 + j] = As[i * ns + j];
        }
        b->B[n0 + i] = Bs[i] * b->vu;
    }
    for (size_t j = 0; j < n0; j++) {
        b->vx[j] *= Ds;
    }
    for (size_t j = 0; j < ns; j++) {
        b->vx[n0 + j] = Cs[j];
    }
    b->vu *= Ds;
    b->n += ns;
    return 0;
}

/* A B of n x n matrices, rows `stride` apart, into P (not A or B). */
static void matmul(const double *A, const double *B, size_t n, size_t stride, double *P)
{
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) {
            double acc = 0.0;
            for (size_t q = 0; q < n; q++) {
                acc += A[i * stride + q] * B[q * stride + j];
            }
            P[i * stride + j] = acc;
        }
    }
}

/* exp(M) of an m x m matrix (row-major, stride MMAX) into E. */
static void expm(const double *M, size_t m, double *E)
{
    double term[MMAX * MMAX], next[MMAX * MMAX];
    double norm = 0.0;
    for (size_t j = 0; j < m; j++) {
        double col = 0.0;
        for (size_t i = 0; i < m; i++) {
            col += fabs(M[i * MMAX + j]);
        }
        norm = col > norm ? col : norm;
    }
    int s = 0;
    while (norm > 0.25 && s < 1000) {
        norm *= 0.5;
        s++;
    }
    const double scale = ldexp(1.0, -s);
    /* ||M / 2^s||_1 <= 1/4: 24 Taylor terms leave less than 1e-30. */
    for (size_t i = 0; i < m; i++) {
        for (size_t j = 0; j < m; j++) {
            E[i * MMAX + j] = (i == j) ? 1.0 : 0.0;
            term[i * MMAX + j] = E[i * MMAX + j];
        }
    }
    for (int k = 1; k <= 24; k++) {
        matmul(term, M, m, MMAX, next);
        for (size_t i = 0; i < m; i++) {
            for (size_t j = 0; j < m; j++) {
                next[i * MMAX + j] = next[i * MMAX + j] * scale / (double)k;
                term[i * MMAX + j] = next[i * MMAX + j];
                E[i * MMAX + j] += next[i * MMAX + j];
            }
        }
    }
    for (int r = 0; r < s; r++) {
        matmul(E, E, m, MMAX, next);
        memcpy(E, next, sizeof next);
    }
}

/* Phi = e^{A h}, Gam = int_0^h e^{A s} ds B, from exp of [[A h, B h], [0, 0]]. */
static void discretize(const build_t *b, double h, double *Phi, double *Gam)
{
    double M[MMAX * MMAX], E[MMAX * MMAX];
    const size_t n = b->n;
    memset(M, 0, sizeof M);
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) {
            M[i * MMAX + j] = b->A[i * NMAX + j] * h;
        }
        M[i * MMAX + n] = b->B[i] * h;
    }
    expm(M, n + 1u, E);
    for (size_t i = 0; i < n; i++) {
        for (size_t j = 0; j < n; j++) {
            Phi[i * n + j] = E[i * MMAX + j];
        }
        Gam[i] = E[i * MMAX + n];
    }
}

static bool desc_ok(const sim_plant_desc_t *d)
{
    size_t poles = d->n_lags + (d->wn > 0.0 ? 2u : 0u) + (d->integrating ? 1u : 0u);
    if (!isfinite(d->K) || !(d->delay >= 0.0) || !isfinite(d->delay) || poles == 0u ||
        d->n_zeros > poles || poles > NMAX || (d->n_lags > 0u && d->lags == NULL) ||
        (d->n_zeros > 0u && d->zeros == NULL) || !(d->wn >= 0.0) || !isfinite(d->wn) ||
        (d->wn > 0.0 && !(d->zeta > 0.0 && isfinite(d->zeta)))) {
        return false;
    }
    for (size_t i = 0; i < d->n_lags; i++) {
        if (!(d->lags[i] > 0.0) || !isfinite(d->lags[i])) {
            return false;
        }
    }
    for (size_t i = 0; i < d->n_zeros; i++) {
        if (d->zeros[i] == 0.0 || !isfinite(d->zeros[i])) {
            return false;
        }
    }
    return true;
}

static int realise(const sim_plant_desc_t *d, build_t *b)
{
    size_t z = 0;
    memset(b, 0, sizeof *b);
    b->vu = d->K;
    for (size_t i = 0; i < d->n_lags; i++) {
        /* (Z s + 1) / (T s + 1) = Z / T + (1 - Z / T) / (T s + 1) */
        const double T = d->lags[i];
        const double c = (z < d->n_zeros) ? d->zeros[z++] / T : 0.0;
        const double As = -1.0 / T, Bs = 1.0 / T, Cs = 1.0 - c;
        if (add_section(b, 1u, &As, &Bs, &Cs, c) != 0) {
            return -1;
        }
    }
    if (d->integrating) {
        /* (Z s + 1) / s = Z + 1 / s */
        const double c = (z < d->n_zeros) ? d->zeros[z++] : 0.0;
        const double As = 0.0, Bs = 1.0, Cs = 1.0;
        if (add_section(b, 1u, &As, &Bs, &Cs, c) != 0) {
            return -1;
        }
    }
    if (d->wn > 0.0) {
        /* wn^2 (z1 s + 1)(z2 s + 1) / (s^2 + 2 zeta wn s + wn^2) with
         * x1' = x2, x2' = -wn^2 x1 - 2 zeta wn x2 + v. */
        const double w2 = d->wn * d->wn, a1 = 2.0 * d->zeta * d->wn;
        const double z1 = (z < d->n_zeros) ? d->zeros[z++] : 0.0;
        const double z2 = (z < d->n_zeros) ? d->zeros[z++] : 0.0;
        const double As[4] = {0.0, 1.0, -w2, -a1};
        const double Bs[2] = {0.0, 1.0};
        const double Cs[2] = {w2 * (1.0 - z1 * z2 * w2), w2 * ((z1 + z2) - a1 * z1 * z2)};
        if (add_section(b, 2u, As, Bs, Cs, w2 * z1 * z2) != 0) {
            return -1;
        }
    }
    return (z == d->n_zeros) ? 0 : -1;
}

/* M v of an n x n matrix into out. */
static void matvec(const double *M, const double *v, size_t n, double *out)
{
    for (size_t i = 0; i < n; i++) {
        double acc = 0.0;
        for (size_t j = 0; j < n; j++) {
            acc += M[i * n + j] * v[j];
        }
        out[i] = acc;
    }
}

/* The ring of past inputs of p over hist: l + 2 entries. */
static int set_history(sim_plant_t *p, size_t l, double *hist, size_t hist_len)
{
    if (hist == NULL || l + 2u > hist_len) {
        return -1;
    }
    p->l = l;
    p->hist = hist;
    p->hist_len = l + 2u;
    return 0;
}

sim_plant_desc_t sim_plant_desc_lags(double K, const double *lags, size_t n_lags, double delay)
{
    sim_plant_desc_t d;
    memset(&d, 0, sizeof d);
    d.K = K;
    d.lags = lags;
    d.n_lags = n_lags;
    d.delay = delay;
    return d;
}

int sim_plant_init(sim_plant_t *p, const sim_plant_desc_t *d, double Ts, double u0, double y0,
                   double *hist, size_t hist_len)
{
    build_t b;
    if (p == NULL || d == NULL || !(Ts > 0.0) || !isfinite(Ts) || !desc_ok(d) ||
        realise(d, &b) != 0) {
        return -1;
    }
    double l = floor(d->delay / Ts + 1e-9);
    double f = d->delay / Ts - l;
    if (f < 1e-9) {
        f = 0.0;
    }
    if (f > 1.0 - 1e-9) {
        l += 1.0;
        f = 0.0;
    }
    if (l + 2.0 > (double)hist_len) {
        return -1;
    }
    memset(p, 0, sizeof *p);
    if (set_history(p, (size_t)l, hist, hist_len) != 0) {
        return -1;
    }
    p->n = b.n;
    p->u0 = u0;
    p->y0 = y0;
    memcpy(p->C, b.vx, b.n * sizeof b.vx[0]);
    p->D = b.vu;
    if (f > 0.0) {
        /* Over f Ts the plant sees u(k - l - 1), over the rest u(k - l):
         * Phi = Phi2 Phi1, Gam = Gam2, Gam_prev = Phi2 Gam1. */
        double Phi1[NMAX * NMAX], Gam1[NMAX], Phi2[NMAX * NMAX];
        discretize(&b, f * Ts, Phi1, Gam1);
        discretize(&b, (1.0 - f) * Ts, Phi2, p->Gam);
        matmul(Phi2, Phi1, b.n, b.n, p->Phi);
        matvec(Phi2, Gam1, b.n, p->Gam_prev);
    } else {
        discretize(&b, Ts, p->Phi, p->Gam);
    }
    sim_plant_reset(p);
    return 0;
}

int sim_plant_init_discrete(sim_plant_t *p, size_t n, size_t l, const double *Phi,
                            const double *Gam, const double *Gam_prev, const double *C,
                            double *hist, size_t hist_len)
{
    if (p == NULL || Phi == NULL || Gam == NULL || Gam_prev == NULL || C == NULL || n == 0u ||
        n > NMAX) {
        return -1;
    }
    for (size_t i = 0; i < n * n; i++) {
        if (!isfinite(Phi[i])) {
            return -1;
        }
    }
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(Gam[i]) || !isfinite(Gam_prev[i]) || !isfinite(C[i])) {
            return -1;
        }
    }
    memset(p, 0, sizeof *p);
    if (set_history(p, l, hist, hist_len) != 0) {
        return -1;
    }
    p->n = n;
    memcpy(p->Phi, Phi, n * n * sizeof Phi[0]);
    memcpy(p->Gam, Gam, n * sizeof Gam[0]);
    memcpy(p->Gam_prev, Gam_prev, n * sizeof Gam_prev[0]);
    memcpy(p->C, C, n * sizeof C[0]);
    sim_plant_reset(p);
    return 0;
}

void sim_plant_reset(sim_plant_t *p)
{
    memset(p->x, 0, sizeof p->x);
    for (size_t i = 0; i < p->hist_len; i++) {
        p->hist[i] = 0.0;
    }
    p->head = 0;
}

/* The input deviation applied `back` scans before the newest. */
static double past(const sim_plant_t *p, size_t back)
{
    return p->hist[(p->head + p->hist_len - back) % p->hist_len];
}

/* The output deviation at the start of the scan: the state's, plus the
 * feedthrough of the delayed input that acts now. */
static double output_dev(const sim_plant_t *p)
{
    double y = 0.0;
    for (size_t i = 0; i < p->n; i++) {
        y += p->C[i] * p->x[i];
    }
    /* Read just before this scan's switch of the delayed input: the plant
     * still sees u(k - l - 1), `l` back from the newest applied u(k - 1). */
    y += p->D * past(p, p->l);
    return y;
}

double sim_plant_output(const sim_plant_t *p)
{
    return p->y0 + output_dev(p);
}

void sim_plant_apply(sim_plant_t *p, double u)
{
    double xn[NMAX];
    const size_t n = p->n;
    p->head = (p->head + 1u) % p->hist_len;
    p->hist[p->head] = u - p->u0;
    const double now = past(p, p->l), before = past(p, p->l + 1u);
    for (size_t i = 0; i < n; i++) {
        double acc = p->Gam[i] * now + p->Gam_prev[i] * before;
        for (size_t j = 0; j < n; j++) {
            acc += p->Phi[i * n + j] * p->x[j];
        }
        xn[i] = acc;
    }
    memcpy(p->x, xn, n * sizeof xn[0]);
}

void sim_plant_freq(const sim_plant_desc_t *d, double w, double *mag, double *phase)
{
    double m = fabs(d->K), p = (d->K < 0.0) ? -3.14159265358979323846 : 0.0;
    size_t i;
    p -= w * d->delay;
    for (i = 0; i < d->n_lags; i++) {
        m /= hypot(1.0, d->lags[i] * w);
        p -= atan(d->lags[i] * w);
    }
    for (i = 0; i < d->n_zeros; i++) {
        m *= hypot(1.0, d->zeros[i] * w);
        p += atan(d->zeros[i] * w);
    }
    if (d->wn > 0.0) {
        const double re = 1.0 - (w / d->wn) * (w / d->wn), im = 2.0 * d->zeta * w / d->wn;
        m /= hypot(re, im);
        p -= atan2(im, re);
    }
    if (d->integrating) {
        m = (w > 0.0) ? m / w : (double)INFINITY;
        p -= 1.57079632679489662;
    }
    *mag = m;
    *phase = p;
}

/* The phase without the sign of K: what decides the crossover. */
static double shape_phase(const sim_plant_desc_t *d, double w)
{
    double mag, ph;
    sim_plant_freq(d, w, &mag, &ph);
    return (d->K < 0.0) ? ph + 3.14159265358979323846 : ph;
}

double sim_plant_ultimate_w(const sim_plant_desc_t *d, double t_scale)
{
    const double pi = 3.14159265358979323846;
    double prev = 0.0;
    for (int k = 0; k <= 800; k++) {
        const double w = 1e-4 / t_scale * pow(10.0, (double)k / 100.0);
        if (shape_phase(d, w) <= -pi) {
            double lo = prev, hi = w;
            for (int it = 0; it < 60; it++) {
                const double mid = 0.5 * (lo + hi);
                if (shape_phase(d, mid) <= -pi) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return 0.5 * (lo + hi);
        }
        prev = w;
    }
    return 0.0;
}

void sim_plant_run(sim_plant_t *p, const double *u, size_t n, double *y)
{
    for (size_t k = 0; k < n; k++) {
        y[k] = sim_plant_output(p);
        sim_plant_apply(p, u[k]);
    }
}
