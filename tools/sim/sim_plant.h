/*
 * The one process simulator of pdtfit's tests, benchmarks, demo and command
 * line:
 *
 *   G(s) = K prod_j (Z_j s + 1) / ( prod_i (T_i s + 1)
 *                                   (s^2 / wn^2 + 2 zeta s / wn + 1) s^integ )
 *          e^{-D s}
 *
 * lags T_i > 0, zeros Z_j != 0 of either sign (a negative Z is a right-half-
 * plane zero), an optional second-order pair (any zeta > 0: complex poles
 * below 1), an optional integrator (K is then the integrating gain per
 * second), any dead time D >= 0. Driven by an input held over each scan
 * (zero-order hold) and read once per scan, before the new input is applied,
 * as a controller sees its process.
 *
 * The rational part is a series of small sections (a lag with a zero when
 * one is left, the integrator, the pair with up to two zeros), whose state
 * equation is integrated exactly over a held input by the matrix exponential
 * (scaling and squaring of a Taylor series): the result does not depend on
 * the scan being short against the lags. A dead time of l + f scans puts
 * one switch of the delayed input inside each scan, at f Ts, so one scan is
 *
 *   x(k+1) = Phi x(k) + Gam u(k - l) + Gam_prev u(k - l - 1),
 *
 * the form a realisation made elsewhere (the autotune benchmark's numpy
 * one) is loaded in too, by sim_plant_init_discrete.
 *
 * C99, double, no allocation and no stdio: it also runs on the target.
 */
#ifndef SIM_PLANT_H
#define SIM_PLANT_H

#include <stdbool.h>
#include <stddef.h>

/* Most states (lags + 2 for the pair + 1 for the integrator). A target
 * short of RAM may define fewer (the AVR's: tests/target/avr). */
#ifndef SIM_PLANT_MAX_STATES
#define SIM_PLANT_MAX_STATES 12u
#endif
/* Length of the input history a dead time of `delay` s at scan `Ts` s
 * needs (whole scans of delay + 2). */
#define SIM_PLANT_HIST_LEN(delay, Ts) ((size_t)((delay) / (Ts) + 1e-9) + 2u)

typedef struct sim_plant_desc {
    double K;           /* DC gain; with `integrating`, the gain per s */
    const double *lags; /* n_lags time constants, s, > 0 */
    size_t n_lags;
    const double *zeros; /* n_zeros numerator time constants, s, != 0 */
    size_t n_zeros;
    double wn;        /* the pair's natural frequency, rad/s; 0: none */
    double zeta;      /* the pair's damping, > 0 */
    bool integrating; /* one more pole at s = 0 */
    double delay;     /* dead time, s, >= 0 */
} sim_plant_desc_t;

typedef struct sim_plant {
    size_t n; /* states */
    double Phi[SIM_PLANT_MAX_STATES * SIM_PLANT_MAX_STATES];
    double Gam[SIM_PLANT_MAX_STATES];      /* the input of l scans ago */
    double Gam_prev[SIM_PLANT_MAX_STATES]; /* the input of l + 1 scans ago */
    double C[SIM_PLANT_MAX_STATES];
    double D;                       /* direct feedthrough */
    double x[SIM_PLANT_MAX_STATES]; /* deviation from rest */
    double *hist;                   /* applied inputs, a ring (caller memory) */
    size_t hist_len;                /* l + 2 used */
    size_t head;                    /* newest entry of hist */
    size_t l;                       /* whole scans of dead time */
    double u0, y0;                  /* the operating point */
} sim_plant_t;

/* The description of K e^{-delay s} / prod_i (lags[i] s + 1), the rest
 * zero; lags must outlive its use. */
sim_plant_desc_t sim_plant_desc_lags(double K, const double *lags, size_t n_lags, double delay);

/* Prepares p at rest: output y0 with the input held at u0 (for an
 * integrating plant, y0 stays while u = u0). Ts > 0, s. hist holds the
 * delayed inputs: at least SIM_PLANT_HIST_LEN(d->delay, Ts) doubles, kept
 * by the caller for p's life. Returns 0, or -1 for a description it
 * cannot simulate (more zeros than poles, a bad value, too many states, a
 * history too short). */
int sim_plant_init(sim_plant_t *p, const sim_plant_desc_t *d, double Ts, double u0, double y0,
                   double *hist, size_t hist_len);

/* Prepares p at rest (u0 = y0 = 0) from a discrete realisation made
 * elsewhere: x(k+1) = Phi x(k) + Gam u(k - l) + Gam_prev u(k - l - 1),
 * y(k) = C x(k), n states (Phi n x n, row-major). hist: at least l + 2
 * doubles, kept by the caller. Returns 0, or -1 for n of 0 or above
 * SIM_PLANT_MAX_STATES, a value that is not finite, or a history too
 * short. */
int sim_plant_init_discrete(sim_plant_t *p, size_t n, size_t l, const double *Phi,
                            const double *Gam, const double *Gam_prev, const double *C,
                            double *hist, size_t hist_len);

/* Back to rest at the operating point, the description kept. */
void sim_plant_reset(sim_plant_t *p);

/* The output now: what a sensor reads at the start of this scan. */
double sim_plant_output(const sim_plant_t *p);

/* Holds u over one scan and advances the plant to the next scan. */
void sim_plant_apply(sim_plant_t *p, double u);

/* y[k] = output read at scan k, with u[k] then applied, k = 0 .. n-1,
 * from rest. */
void sim_plant_run(sim_plant_t *p, const double *u, size_t n, double *y);

/* Frequency response of the described process at w rad/s: magnitude and
 * phase in radians, continuous (not wrapped), -w D included, a negative K
 * as a phase of -pi. */
void sim_plant_freq(const sim_plant_desc_t *d, double w, double *mag, double *phase);

/* The lowest frequency, rad/s, at which the phase reaches -pi (the
 * ultimate frequency a relay test finds), searched up to 1e4 / t_scale
 * with t_scale a typical time of the process (s); 0 when the phase never
 * reaches -pi there. */
double sim_plant_ultimate_w(const sim_plant_desc_t *d, double t_scale);

#endif /* SIM_PLANT_H */
